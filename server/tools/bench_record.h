// omnisweep-bench's recording section (bench_record.cc).
#pragma once

namespace omnisweep::tools {

// Writes 2048x1024-sized RGB-D frames (the default stream's ~850 KB payloads) through
// record::StreamRecorder into a temporary MCAP file as fast as it takes them, then reads them
// back with record::McapReader: MB/s and frames/s each way.
void record_section(bool json);

}  // namespace omnisweep::tools
