#pragma once
// One check macro for every OpenCL call: a failure throws cl::Error naming the call, the status and file:line.
#include <CL/cl.h>

#include <stdexcept>
#include <string>

namespace clr::cl {

// Symbolic name of an OpenCL status code ("CL_OUT_OF_RESOURCES"), or "CL_UNKNOWN_ERROR(<code>)".
std::string status_name(cl_int status);

class Error : public std::runtime_error {
 public:
  Error(cl_int status, const std::string& what) : std::runtime_error(what), status_(status) {}
  cl_int status() const { return status_; }

 private:
  cl_int status_;
};

[[noreturn]] void throw_error(cl_int status, const char* call, const char* file, int line);

}  // namespace clr::cl

#define CLR_CL_CHECK(call)                                                                         \
  do {                                                                                             \
    const cl_int clr_status_ = (call);                                                             \
    if (clr_status_ != CL_SUCCESS) ::clr::cl::throw_error(clr_status_, #call, __FILE__, __LINE__); \
  } while (0)
