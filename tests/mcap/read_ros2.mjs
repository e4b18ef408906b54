// Reads the ROS 2 channels of an omnisweep recording as Foxglove does: @mcap/core's indexed
// reader, each channel's "ros2msg" schema parsed by @foxglove/rosmsg, every message decoded by
// @foxglove/rosmsg2-serialization three times (with the recorded schema, and with the Humble and
// the Jazzy definitions of @foxglove/rosmsg-msgs-common), which must agree. The images are
// decoded too: the JPEG by jpeg-js, the compressedDepth PNG by pngjs, read as
// compressed_depth_image_transport reads it (distance = A / (v - B), 0 = none).
// Prints one JSON object (tests/record_test.cc checks it against the stream); exits 1 on any
// error.
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { ros2humble, ros2jazzy } from "@foxglove/rosmsg-msgs-common";
import jpeg from "jpeg-js";
import { PNG } from "pngjs";
import { open } from "node:fs/promises";
import { crc32 } from "node:zlib";
import { isDeepStrictEqual } from "node:util";

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

// "sensor_msgs/msg/CompressedImage" -> the distro's definitions, root first.
const distroReader = (distro, type) => {
  const root = distro[type.replace("/msg/", "/")];
  if (!root) throw new Error(`no ${type} in the distro's definitions`);
  return new MessageReader([root, ...Object.values(distro)]);
};
const channels = [];
const readers = new Map();
for (const channel of reader.channelsById.values()) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (schema?.encoding !== "ros2msg") continue;
  const text = new TextDecoder().decode(schema.data);
  readers.set(channel.id, [
    new MessageReader(parse(text, { ros2: true })),
    distroReader(ros2humble, schema.name),
    distroReader(ros2jazzy, schema.name),
  ]);
  channels.push({
    topic: channel.topic,
    schemaName: schema.name,
    messageEncoding: channel.messageEncoding,
    offeredQos: channel.metadata.get("offered_qos_profiles") ?? "",
  });
}

// Typed arrays as plain arrays, so the three decodings compare by value.
const plain = (v) =>
  ArrayBuffer.isView(v) ? Array.from(v) : Array.isArray(v) ? v.map(plain)
  : v && typeof v === "object" ? Object.fromEntries(Object.entries(v).map(([k, x]) => [k, plain(x)]))
  : v;
const stamp = (h) => (BigInt(h.stamp.sec) * 1000000000n + BigInt(h.stamp.nanosec ?? h.stamp.nsec)).toString();

const messages = [];
for await (const record of reader.readMessages()) {
  const decoders = readers.get(record.channelId);
  if (!decoders) continue;
  const [ours, humble, jazzy] = decoders.map((d) => d.readMessage(record.data));
  if (!isDeepStrictEqual(plain(ours), plain(humble)) || !isDeepStrictEqual(plain(ours), plain(jazzy)))
    throw new Error(`message on ${reader.channelsById.get(record.channelId).topic} decodes differently`);
  const topic = reader.channelsById.get(record.channelId).topic;
  const m = ours;
  const out = { topic };
  if (topic.endsWith("/color/image_raw/compressed")) {
    const image = jpeg.decode(m.data, { useTArray: true });
    Object.assign(out, { stamp: stamp(m.header), frame: m.header.frame_id, format: m.format,
      bytes: m.data.length, crc32: crc32(m.data), width: image.width, height: image.height });
  } else if (topic.endsWith("/distance/image_raw/compressedDepth")) {
    const view = new DataView(m.data.buffer, m.data.byteOffset, 12);
    const [format, a, b] = [view.getInt32(0, true), view.getFloat32(4, true), view.getFloat32(8, true)];
    const png = PNG.sync.read(Buffer.from(m.data.subarray(12)), { skipRescale: true });
    if (png.depth !== 16) throw new Error(`compressedDepth PNG has depth ${png.depth}`);
    // pngjs keeps 16-bit samples in a Uint16Array of RGBA; the grey value is the first channel.
    const samples = [];
    for (let i = 0; i < png.width * png.height; i += 97) {
      const v = png.data[4 * i];
      samples.push([i, v === 0 ? null : Math.fround(a / (Math.fround(v) - b))]);
    }
    Object.assign(out, { stamp: stamp(m.header), format: m.format, depthFormat: format,
      width: png.width, height: png.height, bytes: m.data.length, samples });
  } else if (topic.endsWith("/distance/image_raw")) {
    Object.assign(out, { stamp: stamp(m.header), encoding: m.encoding, width: m.width,
      height: m.height, bytes: m.data.length });
  } else if (topic.endsWith("/points")) {
    Object.assign(out, { stamp: stamp(m.header), frame: m.header.frame_id, width: m.width,
      height: m.height, fields: m.fields.map((f) => f.name), bytes: m.data.length });
  } else if (topic === "/tf_static") {
    out.children = m.transforms.map((t) => t.child_frame_id);
    out.parent = m.transforms[0]?.header.frame_id;
  } else if (topic === "/diagnostics") {
    out.fps = m.status[0]?.values.find((kv) => kv.key === "fps")?.value ?? null;
  }
  messages.push(out);
}
console.log(JSON.stringify({ profile: reader.header.profile, channels, messages }));
await handle.close();
