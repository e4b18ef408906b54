// The line omnisweep-view and omnisweep-subscribe print each second while a server is matched but
// its first frame has not arrived: a server on a CPU device can take tens of seconds over it, and
// its status says what it is doing meanwhile.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

#include "omnisweep/wire/server_status.h"

namespace omnisweep::tools {

inline std::string waiting_line(const std::optional<wire::StatusReport>& status) {
  std::string line = "waiting for the first frame";
  if (!status) return line + " (no status from the server yet)";
  std::string stages;
  for (const auto& [stage, ms] : status->stage_ms) {
    if (ms <= 0) continue;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s %s %.0f ms", stages.empty() ? "" : ",", stage.c_str(), ms);
    stages += buf;
  }
  return line + " (server " + status->state +
         (stages.empty() ? ", no stage has finished a frame yet)" : "; per frame:" + stages + ")");
}

}  // namespace omnisweep::tools
