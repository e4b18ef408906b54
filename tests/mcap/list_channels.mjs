// Reads an MCAP file with Foxglove's @mcap/core and prints, as one JSON object, its channels
// (topic, message and schema encodings, schema name) and message counts: from the summary's
// statistics and by reading every message through the indexed reader. Exits 1 on any error.
import { McapIndexedReader } from "@mcap/core";
import { open } from "node:fs/promises";

const path = process.argv[2];
const handle = await open(path, "r");
const size = (await handle.stat()).size;
const readable = {
  size: async () => BigInt(size),
  read: async (offset, length) => {
    const buffer = new Uint8Array(Number(length));
    await handle.read(buffer, 0, Number(length), Number(offset));
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({ readable });
const counted = {};
for await (const message of reader.readMessages()) {
  const topic = reader.channelsById.get(message.channelId).topic;
  counted[topic] = (counted[topic] ?? 0) + 1;
}
const channels = [...reader.channelsById.values()].map((c) => ({
  topic: c.topic,
  messageEncoding: c.messageEncoding,
  schemaName: reader.schemasById.get(c.schemaId)?.name ?? "",
  schemaEncoding: reader.schemasById.get(c.schemaId)?.encoding ?? "",
  statistics: Number(reader.statistics?.channelMessageCounts.get(c.id) ?? -1n),
  read: counted[c.topic] ?? 0,
}));
console.log(JSON.stringify({ chunks: reader.chunkIndexes.length, channels }));
await handle.close();
