// omnisweep-bench's security section (bench_security.cc).
#pragma once

#include <string>

namespace omnisweep::tools {

// Streams real 2048x1024 frames (the synthetic rig's panorama, JPEG q90 + qinv16-zstd) at 30 Hz
// from this process to an omnisweep-subscribe process on loopback, once plain and once with DDS
// Security (credentials made by deploy/security/make-credentials.sh in a temporary folder):
// frames delivered per second and latency from publish to decoded.
void security_section(const std::string& source_dir, bool json);

}  // namespace omnisweep::tools
