// libFuzzer target: the MCAP reader (client_sdk/src/record) on arbitrary files, and the CDR
// decoding of every message it yields as the type its channel names, as omnisweep-play does.
// The input goes to an in-memory file (memfd) that the reader opens by path.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "omnisweep/record/stream_recording.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace omnisweep;
  static const int fd = memfd_create("omnisweep-fuzz-mcap", 0);
  if (fd < 0 || ftruncate(fd, 0) != 0 || pwrite(fd, data, size, 0) != ssize_t(size)) return 0;
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  try {
    record::McapReader reader(path);
    msg::StreamDescription description;
    msg::RgbdFrame frame;
    msg::ServerStatus status;
    reader.read([&](const record::McapMessage& m) {
      try {
        switch (record::recorded_topic(reader, *m.channel).value_or(dds::TopicKind(-1))) {
          case dds::TopicKind::kDescription:
            record::decode_message(m.data, description);
            break;
          case dds::TopicKind::kFrames:
            record::decode_message(m.data, frame);
            break;
          case dds::TopicKind::kStatus:
            record::decode_message(m.data, status);
            break;
          default:
            break;
        }
      } catch (const std::exception&) {
      }
      return true;
    });
  } catch (const std::exception&) {
  }
  return 0;
}
