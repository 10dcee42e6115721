// What a result file says about where and how its numbers were measured: the
// command line as given and the machine (CPU, cores, OS, compiler and build).
// Every command that writes a result file heads it with these.
#pragma once

#include <string>

namespace foveart::toolkit {

// "CPU model, N cores; OS, Linux release; compiler, build type", e.g.
// "AMD EPYC 7763 64-Core Processor, 2 cores; Debian GNU/Linux 12 (bookworm),
// Linux 6.1.0-18-amd64; GCC 12.2.0, RelWithDebInfo". Parts it cannot read say "unknown".
std::string machine_description();

// Records the command line this process was started with (run_cli does it).
void set_command_line(int argc, const char* const* argv);

// The recorded command line, each argument quoted for a POSIX shell where it
// needs it; "" when none was recorded.
const std::string& command_line();

// One argument quoted for a POSIX shell where it needs it ('it''s' -> 'it'\''s').
std::string shell_quote(const std::string& arg);

// The markdown head of a result file: "Written by `COMMAND` on MACHINE." plus a
// line saying the numbers below come from that run.
std::string result_header(const std::string& command);

}  // namespace foveart::toolkit
