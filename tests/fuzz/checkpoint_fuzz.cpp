// The checkpoint reader on arbitrary bytes: bad input must end in InputError. The checksum guards the payload, so
// a fuzzer would rarely get past it; the harness therefore also wraps its input as a payload with a valid header
// (the first byte picks which), to reach the payload parser with hostile sizes.
#include <cstdint>
#include <cstring>
#include <string>

#include "common/error.hpp"
#include "fuzz/fuzz_input.hpp"
#include "nn/checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::string file(reinterpret_cast<const char*>(data + 1), size - 1);
  if (data[0] & 1) {
    const std::string payload = file;
    file.assign("CLRCKPT\n", 8);
    const std::uint32_t words[2] = {clr::nn::kCheckpointVersion, 0};
    const std::uint64_t longs[2] = {payload.size(), clr::nn::fnv1a64(payload.data(), payload.size())};
    file.append(reinterpret_cast<const char*>(words), sizeof words);
    file.append(reinterpret_cast<const char*>(longs), sizeof longs);
    file += payload;
  }
  const auto path =
      clr::fuzz::write_input("model.clr", reinterpret_cast<const std::uint8_t*>(file.data()), file.size());
  try {
    (void)clr::nn::read_checkpoint(path.string());
  } catch (const clr::InputError&) {
  }
  return 0;
}
