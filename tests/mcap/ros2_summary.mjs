// Decoding and summarising omnisweep's ROS 2 messages as Foxglove does, shared by read_ros2.mjs
// (recordings) and foxglove_client.mjs (the live WebSocket server): each message is decoded by
// @foxglove/rosmsg2-serialization three times, with the schema we sent (parsed by
// @foxglove/rosmsg) and with the Humble and the Jazzy definitions of
// @foxglove/rosmsg-msgs-common, which must agree; images are decoded too (jpeg-js, pngjs).
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { ros2humble, ros2jazzy } from "@foxglove/rosmsg-msgs-common";
import jpeg from "jpeg-js";
import { PNG } from "pngjs";
import { crc32 } from "node:zlib";
import { isDeepStrictEqual } from "node:util";

// "sensor_msgs/msg/CompressedImage" -> the distro's definitions, root first.
const distroReader = (distro, type) => {
  const root = distro[type.replace("/msg/", "/")];
  if (!root) throw new Error(`no ${type} in the distro's definitions`);
  return new MessageReader([root, ...Object.values(distro)]);
};

export function makeDecoder(schemaName, schemaText) {
  const readers = [
    new MessageReader(parse(schemaText, { ros2: true })),
    distroReader(ros2humble, schemaName),
    distroReader(ros2jazzy, schemaName),
  ];
  return (topic, data) => {
    const [ours, humble, jazzy] = readers.map((r) => r.readMessage(data));
    if (!isDeepStrictEqual(plain(ours), plain(humble)) || !isDeepStrictEqual(plain(ours), plain(jazzy)))
      throw new Error(`a message on ${topic} decodes differently under the three definitions`);
    return ours;
  };
}

// Typed arrays as plain arrays, so decodings compare by value.
const plain = (v) =>
  ArrayBuffer.isView(v) ? Array.from(v)
  : Array.isArray(v) ? v.map(plain)
  : v && typeof v === "object" ? Object.fromEntries(Object.entries(v).map(([k, x]) => [k, plain(x)]))
  : v;
const stamp = (h) => (BigInt(h.stamp.sec) * 1000000000n + BigInt(h.stamp.nanosec ?? h.stamp.nsec)).toString();

// What the C++ tests check against the stream.
export function summarize(topic, m) {
  const out = { topic };
  if (topic.endsWith("/color/image_raw/compressed")) {
    const image = jpeg.decode(m.data, { useTArray: true });
    Object.assign(out, { stamp: stamp(m.header), frame: m.header.frame_id, format: m.format,
      bytes: m.data.length, crc32: crc32(m.data), width: image.width, height: image.height });
  } else if (topic.endsWith("/distance/image_raw/compressedDepth")) {
    // compressed_depth_image_transport's layout: int32 format (0 = inverse depth), float A,
    // float B, then a 16-bit PNG; distance = A / (v - B), 0 = none.
    const view = new DataView(m.data.buffer, m.data.byteOffset, 12);
    const [format, a, b] = [view.getInt32(0, true), view.getFloat32(4, true), view.getFloat32(8, true)];
    const png = PNG.sync.read(Buffer.from(m.data.subarray(12)), { skipRescale: true });
    if (png.depth !== 16) throw new Error(`compressedDepth PNG has depth ${png.depth}`);
    const samples = [];  // pngjs keeps 16-bit grey as the first of four channels
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
    const view = new DataView(m.data.buffer, m.data.byteOffset, m.data.byteLength);
    const points = [];  // every 37th point's x, y, z (null where it has none)
    for (let i = 0; i < m.width * m.height; i += 37) {
      const x = view.getFloat32(i * m.point_step, true);
      points.push(Number.isNaN(x) ? null : [x, view.getFloat32(i * m.point_step + 4, true),
        view.getFloat32(i * m.point_step + 8, true)]);
    }
    Object.assign(out, { stamp: stamp(m.header), frame: m.header.frame_id, width: m.width,
      height: m.height, fields: m.fields.map((f) => f.name), bytes: m.data.length, points });
  } else if (topic === "/tf_static") {
    out.children = m.transforms.map((t) => t.child_frame_id);
    out.parent = m.transforms[0]?.header.frame_id;
  } else if (topic === "/diagnostics") {
    out.fps = m.status[0]?.values.find((kv) => kv.key === "fps")?.value ?? null;
  }
  return out;
}
