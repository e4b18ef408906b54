// Clients of omnisweep's Foxglove WebSocket server (tests/ros2_test.cc runs them).
//   collect URL FRAMES   @foxglove/ws-protocol's FoxgloveClient subscribes to every advertised
//                        channel and decodes each message (ros2_summary.mjs) until it holds
//                        FRAMES messages of every frame topic, /tf_static and /diagnostics; prints
//                        {"serverInfo", "channels", "messages"} as JSON.
//   stall URL FRAMES     one client subscribes to everything and stops reading (its socket
//                        paused), another to the colour, which must still get FRAMES messages;
//                        prints the counts.
//   abuse URL            a raw WebSocket client sends bad messages (malformed JSON, unknown op,
//                        unknown channel, an oversized text, a binary message): each must get an
//                        error status and the connection must live on and serve a subscription;
//                        a client asking for no subprotocol is refused. Prints what came back.
// Exits 1 on a timeout or any error.
import wsProtocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;  // a CommonJS package
import { makeDecoder, summarize } from "./ros2_summary.mjs";

const [mode, url, framesArg] = process.argv.slice(2);
const frames = Number(framesArg ?? 1);
const fail = (why) => {
  console.error(`foxglove_client: ${why}`);
  process.exit(1);
};
setTimeout(() => fail("timed out"), 90000).unref();

function connect(subprotocol = FoxgloveClient.SUPPORTED_SUBPROTOCOL) {
  return new FoxgloveClient({ ws: new WebSocket(url, [subprotocol]) });
}

async function collect() {
  const client = connect();
  const channels = new Map();
  const decoders = new Map();
  const messages = [];
  const counts = {};
  let serverInfo;
  client.on("error", (e) => fail(`client error: ${e.message ?? e}`));
  client.on("serverInfo", (info) => (serverInfo = info));
  client.on("advertise", (list) => {
    for (const c of list) {
      if (c.schemaEncoding !== "ros2msg" || c.encoding !== "cdr")
        fail(`channel ${c.topic}: ${c.encoding} / ${c.schemaEncoding}`);
      const id = client.subscribe(c.id);
      channels.set(id, c);
      decoders.set(id, makeDecoder(c.schemaName, c.schema));
    }
  });
  await new Promise((resolve) => {
    client.on("message", ({ subscriptionId, timestamp, data }) => {
      const c = channels.get(subscriptionId);
      if (!c) fail(`a message for subscription ${subscriptionId}, never made`);
      const summary = summarize(c.topic, decoders.get(subscriptionId)(c.topic, data));
      summary.timestamp = timestamp.toString();
      messages.push(summary);
      counts[c.topic] = (counts[c.topic] ?? 0) + 1;
      const done = [...channels.values()].every((ch) =>
        (counts[ch.topic] ?? 0) >= (ch.topic === "/tf_static" || ch.topic === "/diagnostics" ? 1 : frames));
      if (done) resolve();
    });
  });
  client.close();
  console.log(JSON.stringify({ serverInfo, channels: [...channels.values()].map((c) =>
    ({ id: c.id, topic: c.topic, schemaName: c.schemaName })), messages }));
}

async function stall() {
  // Raw sockets: the stalled one must stop reading at the TCP level, which FoxgloveClient hides.
  const open = (onMessage, everything) => new Promise((resolve) => {
    const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    ws.on("error", (e) => fail(`socket error: ${e.message}`));
    ws.on("message", (data, binary) => {
      if (!binary) {
        const m = JSON.parse(data.toString());
        if (m.op === "advertise") {
          const wanted = everything ? m.channels
            : m.channels.filter((c) => c.topic.endsWith("/color/image_raw/compressed"));
          ws.send(JSON.stringify({ op: "subscribe",
            subscriptions: wanted.map((c, i) => ({ id: i + 1, channelId: c.id })) }));
          resolve(ws);
        }
        return;
      }
      onMessage(data);
    });
  });
  let stalledGot = 0, liveGot = 0, liveBytes = 0;
  const stalled = await open(() => ++stalledGot, true);
  stalled._socket.pause();  // reads nothing more: the server's queue for it fills
  const start = Date.now();
  await new Promise((resolve) => {
    open((data) => {
      ++liveGot;
      liveBytes += data.length;
      if (liveGot >= frames) resolve();
    });
  });
  console.log(JSON.stringify({ live: liveGot, liveBytes, stalled: stalledGot,
    seconds: (Date.now() - start) / 1000 }));
  process.exit(0);
}

async function abuse() {
  const refused = await new Promise((resolve) => {
    const ws = new WebSocket(url, ["not-foxglove"]);
    ws.on("open", () => resolve("accepted"));
    ws.on("error", (e) => resolve(e.message));
    ws.on("unexpected-response", (_req, res) => resolve(`HTTP ${res.statusCode}`));
  });
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const statuses = [];
  let colorId, gotMessage = false;
  ws.on("error", (e) => fail(`socket error: ${e.message}`));
  await new Promise((resolve) => {
    ws.on("message", (data, binary) => {
      if (binary) {
        if (data[0] === 1) gotMessage = true;
        resolve();
        return;
      }
      const m = JSON.parse(data.toString());
      if (m.op === "advertise") {
        colorId = m.channels.find((c) => c.topic.endsWith("/color/image_raw/compressed")).id;
        ws.send("{not json");
        ws.send(JSON.stringify({ op: "getParameters", parameterNames: [] }));
        ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 5, channelId: 99999 }] }));
        ws.send(JSON.stringify({ op: "unsubscribe", subscriptionIds: [42] }));
        ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: colorId }], pad: "x".repeat(200000) }));
        ws.send(Buffer.from([2, 0, 0, 0, 0]));
        ws.send("[".repeat(5000));
      } else if (m.op === "status") {
        statuses.push(m);
        if (statuses.length === 7)
          ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: colorId }] }));
      }
    });
  });
  ws.close();
  console.log(JSON.stringify({ refused, statuses, gotMessage }));
}

const run = { collect, stall, abuse }[mode];
if (!run) fail(`unknown mode ${mode}`);
await run();
