#pragma once
// The safetensors file format (https://huggingface.co/docs/safetensors), written so that PyTorch, JAX and numpy
// users can open a model without clradiosity (`clradiosity export`, radiosity/export.hpp):
//
//   offset 0   u64 little-endian  N, the header's size in bytes
//          8   N bytes            JSON: {"__metadata__": {string: string}, NAME: {"dtype": "F32", "shape": [...],
//                                 "data_offsets": [begin, end]}, ...}, padded with spaces to a multiple of 8
//          8 + N                  the tensors' bytes, little-endian, row-major, back to back in header order;
//                                 data_offsets are relative to this point
//
// Only float32 tensors: every tensor the engine keeps is one. Needs only common/.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace clr::nn {

struct SafeTensor {
  std::string name;
  std::vector<std::uint64_t> shape;  // row-major; the product is values.size()
  std::vector<float> values;
};

struct SafeTensors {
  std::map<std::string, std::string> metadata;  // the format allows strings only
  std::vector<SafeTensor> tensors;              // names unique
};

// Written atomically (common/atomic_file.hpp). std::invalid_argument for a duplicate name or a shape that does not
// match its values: a caller's mistake, not the user's.
void write_safetensors(const std::filesystem::path& path, const SafeTensors& file);
// InputError naming `path` when it is not a safetensors file of float32 tensors (truncated, overlapping or
// uncovered data, a malformed header). Tensors come back in the order of their data.
SafeTensors read_safetensors(const std::filesystem::path& path);

}  // namespace clr::nn
