#pragma once
#include <CL/cl.h>

#include <string>
#include <vector>

#include "cl/handle.hpp"
#include "cl/kernel.hpp"

namespace clr::cl {

class Context;

// The source a program of these kernel files is built from: each file after a #line directive naming it (so
// compiler messages point at the right file and line), in order. Tests compile the same text for other targets.
std::string compose_source(const std::vector<std::string>& files);

class Program {
 public:
  // Builds from kernel files; throws cl::Error(CL_BUILD_PROGRAM_FAILURE) whose message holds the build log. What the
  // compiler writes to the process's stdout or stderr while it builds ("31 warnings generated.") is taken into the
  // log rather than left on the user's terminal.
  Program(const Context& ctx, const std::vector<std::string>& files, const std::string& options);
  Kernel kernel(const char* name) const;
  cl_program get() const { return program_.get(); }
  // The compiler's messages of a successful build (the runtime's build log and what it printed): empty when clean.
  const std::string& build_log() const { return log_; }
  // The files it was built from, for messages.
  const std::string& names() const { return names_; }

 private:
  const Context* ctx_;
  ProgramHandle program_;
  std::string log_, names_;
};

// Whether a build log holds a compiler warning (or error) rather than informational lines.
bool has_warning(const std::string& build_log);

}  // namespace clr::cl
