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
  // Builds from kernel files; throws cl::Error(CL_BUILD_PROGRAM_FAILURE) whose message holds the build log.
  Program(const Context& ctx, const std::vector<std::string>& files, const std::string& options);
  Kernel kernel(const char* name) const;
  cl_program get() const { return program_.get(); }

 private:
  const Context* ctx_;
  ProgramHandle program_;
};

}  // namespace clr::cl
