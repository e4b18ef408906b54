// The flags every omnisweep-* program on DDS shares: --domain, --topic-prefix, --qos.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "omnisweep/dds/participant.h"

namespace omnisweep::tools {

inline void add_dds_flags(CLI::App& app, dds::ParticipantOptions& options,
                          const std::string& prefix_help = "Topic prefix of the server") {
  app.add_option("--domain", options.domain, "DDS domain id (0-232)")->check(CLI::Range(0, 232));
  app.add_option("--topic-prefix", options.topic_prefix,
                 prefix_help + "; topics are <prefix>/description, <prefix>/rgbd, <prefix>/status");
  app.add_option("--qos", options.qos_file,
                 "Fast DDS XML profile file (default: deploy/qos/omnisweep_qos.xml, built in)")
      ->check(CLI::ExistingFile);
  app.add_option("--security", options.security_dir,
                 "DDS Security credentials folder (deploy/security/make-credentials.sh): "
                 "authentication, encryption, access control");
}

}  // namespace omnisweep::tools
