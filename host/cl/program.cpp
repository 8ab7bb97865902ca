#include "cl/program.hpp"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <mutex>

#include "cl/context.hpp"
#include "cl/error.hpp"
#include "cl/kernel_source.hpp"
#include "common/address_space.hpp"

namespace clr::cl {
namespace {

std::string runtime_build_log(cl_program program, cl_device_id device) {
  std::size_t n = 0;
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
  std::string log(n, '\0');
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
  return log.c_str();
}

// Holds the process's stderr in a temporary file for its lifetime: a runtime that compiles in-process (PoCL's clang)
// prints its diagnostics there. text() restores it and returns what was written. Only stderr: a host program's
// output on stdout (Python's print from another thread) is never taken. One capture at a time (the mutex): a second
// would save the first one's file as the stream to restore.
class CapturedOutput {
 public:
  CapturedOutput() : lock_(mutex()) {
    std::fflush(stderr);
    std::cerr.flush();
    FILE* f = std::tmpfile();
    if (!f) return;  // nothing to capture into: the output stays where it was
    file_ = f;
    saved_ = ::dup(2);
    if (saved_ < 0 || ::dup2(::fileno(f), 2) < 0) restore();
  }
  ~CapturedOutput() {
    restore();
    if (file_) std::fclose(file_);
  }
  CapturedOutput(const CapturedOutput&) = delete;
  CapturedOutput& operator=(const CapturedOutput&) = delete;

  std::string text() {
    restore();
    std::string out;
    if (!file_) return out;
    std::rewind(file_);
    char chunk[4096];
    for (std::size_t n; (n = std::fread(chunk, 1, sizeof chunk, file_)) > 0;) out.append(chunk, n);
    std::fclose(file_);
    file_ = nullptr;
    return out;
  }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  void restore() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
      saved_ = -1;
    }
  }
  std::lock_guard<std::mutex> lock_;
  FILE* file_ = nullptr;
  int saved_ = -1;
};

}  // namespace

bool has_warning(const std::string& build_log) {
  return build_log.find("warning") != std::string::npos || build_log.find("error") != std::string::npos;
}

std::string compose_source(const std::vector<std::string>& files) {
  std::string source;
  for (const auto& f : files) source += "#line 1 \"" + f + "\"\n" + kernel_source(f) + "\n";
  return source;
}

Program::Program(const Context& ctx, const std::vector<std::string>& files, const std::string& options) : ctx_(&ctx) {
  const std::string source = compose_source(files);
  std::string names;
  for (const auto& f : files) names += (names.empty() ? "" : ", ") + f;
  names_ = names;
  const char* text = source.c_str();
  const std::size_t length = source.size();
  cl_int status = CL_SUCCESS;
  program_ = ProgramHandle(clCreateProgramWithSource(ctx.get(), 1, &text, &length, &status));
  CLR_CL_CHECK(status);
  const cl_device_id device = ctx.device().device;
  std::string printed;
  {
    CapturedOutput captured;
    status = clBuildProgram(program_.get(), 1, &device, options.c_str(), nullptr, nullptr);
    printed = captured.text();
  }
  log_ = runtime_build_log(program_.get(), device);
  // The runtime's log first; what it printed only where the log does not already hold it.
  if (!printed.empty() && log_.find(printed) == std::string::npos) log_ += (log_.empty() ? "" : "\n") + printed;
  // A CPU runtime's compiler that ran out of address space says only that the build failed: said as what it is.
  if (status != CL_SUCCESS && ctx.device().type == DeviceType::Cpu)
    require_address_space(0, 0, "building OpenCL program [" + names + "]");
  if (status != CL_SUCCESS) {
    throw Error(status, "building OpenCL program [" + names + "] with options '" + options + "' on " +
                            ctx.device().name + " failed with " + status_name(status) + "; build log:\n" + log_);
  }
}

Kernel Program::kernel(const char* name) const {
  cl_int status = CL_SUCCESS;
  KernelHandle k(clCreateKernel(program_.get(), name, &status));
  if (status != CL_SUCCESS)
    throw Error(status, std::string("clCreateKernel('") + name + "') failed with " + status_name(status));
  return Kernel(*ctx_, std::move(k), name);
}

}  // namespace clr::cl
