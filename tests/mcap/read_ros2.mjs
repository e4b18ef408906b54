// Reads the ROS 2 channels of an omnisweep recording as Foxglove does: @mcap/core's indexed
// reader, then every message decoded and summarised by ros2_summary.mjs (the recorded schema,
// Humble's and Jazzy's definitions must agree; JPEG and compressedDepth PNG decoded).
// Prints one JSON object (tests/ros2_test.cc checks it against the stream); exits 1 on any
// error.
import { McapIndexedReader } from "@mcap/core";
import { open } from "node:fs/promises";
import { makeDecoder, summarize } from "./ros2_summary.mjs";

const path = process.argv[2];
const handle = await open(path, "r");
const size = (await handle.stat()).size;
const reader = await McapIndexedReader.Initialize({
  readable: {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buffer = new Uint8Array(Number(length));
      await handle.read(buffer, 0, Number(length), Number(offset));
      return buffer;
    },
  },
});

const channels = [];
const readers = new Map();
for (const channel of reader.channelsById.values()) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (schema?.encoding !== "ros2msg") continue;
  const text = new TextDecoder().decode(schema.data);
  readers.set(channel.id, makeDecoder(schema.name, text));
  channels.push({
    topic: channel.topic,
    schemaName: schema.name,
    messageEncoding: channel.messageEncoding,
    offeredQos: channel.metadata.get("offered_qos_profiles") ?? "",
  });
}

const messages = [];
for await (const record of reader.readMessages()) {
  const decode = readers.get(record.channelId);
  if (!decode) continue;
  const topic = reader.channelsById.get(record.channelId).topic;
  messages.push(summarize(topic, decode(topic, record.data)));
}
console.log(JSON.stringify({ profile: reader.header.profile, channels, messages }));
await handle.close();
