#include "cl/program.hpp"

#include "cl/context.hpp"
#include "cl/error.hpp"
#include "cl/kernel_source.hpp"

namespace clr::cl {
namespace {

std::string build_log(cl_program program, cl_device_id device) {
  std::size_t n = 0;
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
  std::string log(n, '\0');
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
  return log.c_str();
}

}  // namespace

std::string compose_source(const std::vector<std::string>& files) {
  std::string source;
  for (const auto& f : files) source += "#line 1 \"" + f + "\"\n" + kernel_source(f) + "\n";
  return source;
}

Program::Program(const Context& ctx, const std::vector<std::string>& files, const std::string& options) : ctx_(&ctx) {
  const std::string source = compose_source(files);
  std::string names;
  for (const auto& f : files) names += (names.empty() ? "" : ", ") + f;
  const char* text = source.c_str();
  const std::size_t length = source.size();
  cl_int status = CL_SUCCESS;
  program_ = ProgramHandle(clCreateProgramWithSource(ctx.get(), 1, &text, &length, &status));
  CLR_CL_CHECK(status);
  const cl_device_id device = ctx.device().device;
  status = clBuildProgram(program_.get(), 1, &device, options.c_str(), nullptr, nullptr);
  if (status != CL_SUCCESS) {
    throw Error(status, "building OpenCL program [" + names + "] with options '" + options + "' on " +
                            ctx.device().name + " failed with " + status_name(status) + "; build log:\n" +
                            build_log(program_.get(), device));
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
