#pragma once
#include <CL/cl.h>

#include <string>
#include <vector>

#include "cl/handle.hpp"
#include "cl/kernel.hpp"

namespace clr::cl {

class Context;

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
