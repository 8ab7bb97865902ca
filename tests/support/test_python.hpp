#pragma once
// The tests' Python: a venv (.ci/install-python-test-deps) made from the interpreter the module was built for, with
// numpy, safetensors and pytest from PyPI. "" where it cannot be made (no network, no python3-venv): the tests that
// need it skip.
#include <cstdlib>
#include <string>

namespace clr::test {

inline std::string test_python() {
  const std::string venv = CLR_PYTHON_VENV, py = venv + "/bin/python";
  const std::string install = "bash '" CLR_SOURCE_DIR "/.ci/install-python-test-deps' '" + venv +
                              "' '" CLR_PYTHON_EXECUTABLE "' >/dev/null 2>&1";
  if (std::system(install.c_str()) != 0) return "";
  return std::system(("'" + py + "' -c 'import safetensors, numpy, pytest' 2>/dev/null").c_str()) == 0 ? py : "";
}

}  // namespace clr::test
