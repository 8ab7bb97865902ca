#include "radiosity/environment.hpp"

#include "cl/device.hpp"
#include "cl/kernel_source.hpp"
#include "radiosity/trainer.hpp"

namespace clr::radiosity {

void check_environment() {
  cl::check_kernel_environment();  // CLRADIOSITY_KERNEL_DIR, CLRADIOSITY_KERNEL_WARNINGS
  cl::emulating_nvidia_limits();   // CLRADIOSITY_EMULATE_LIMITS
  default_schedule();              // CLRADIOSITY_STEP_SCHEDULE
}

}  // namespace clr::radiosity
