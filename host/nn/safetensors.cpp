#include "nn/safetensors.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr::nn {
namespace {

static_assert(std::endian::native == std::endian::little, "safetensors data is little-endian; so is this host's");

// The reference implementation refuses headers above 100 MB; a model's header is a few kilobytes.
constexpr std::uint64_t kMaxHeader = 100'000'000;

std::uint64_t product(const std::vector<std::uint64_t>& shape) {
  std::uint64_t n = 1;
  for (const auto d : shape) n *= d;
  return n;
}

}  // namespace

void write_safetensors(const std::filesystem::path& path, const SafeTensors& file) {
  // ordered_json keeps the tensors in the order of their data, so the header reads like the file.
  nlohmann::ordered_json header = nlohmann::ordered_json::object();
  if (!file.metadata.empty()) header["__metadata__"] = file.metadata;
  std::set<std::string> names;
  std::uint64_t offset = 0;
  for (const auto& t : file.tensors) {
    if (t.name == "__metadata__" || !names.insert(t.name).second)
      throw std::invalid_argument("safetensors: tensor name '" + t.name + "' is reserved or repeated");
    if (product(t.shape) != t.values.size())
      throw std::invalid_argument("safetensors: tensor '" + t.name + "': shape does not match its values");
    const std::uint64_t bytes = t.values.size() * sizeof(float);
    header[t.name] = {{"dtype", "F32"}, {"shape", t.shape}, {"data_offsets", {offset, offset + bytes}}};
    offset += bytes;
  }
  std::string text = header.dump();
  // Aligning the data to 8 bytes lets readers map it in place (the reference writer pads the same way).
  text.append((8 - text.size() % 8) % 8, ' ');
  const std::uint64_t size = text.size();
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(text.data(), std::streamsize(text.size()));
    for (const auto& t : file.tensors)
      out.write(reinterpret_cast<const char*>(t.values.data()), std::streamsize(t.values.size() * sizeof(float)));
    out.close();
    if (!out) throw std::runtime_error("writing " + path.string() + " failed (disk full?)");
  });
}

SafeTensors read_safetensors(const std::filesystem::path& path) {
  const std::string data = read_input_text(path, "safetensors file");
  const auto fail = [&](const std::string& what) -> InputError {
    return InputError("safetensors file " + path.string() + ": " + what);
  };
  std::uint64_t size = 0;
  if (data.size() < sizeof size) throw fail("shorter than its 8-byte header size");
  std::memcpy(&size, data.data(), sizeof size);
  if (size > kMaxHeader || size > data.size() - sizeof size)
    throw fail("header size " + std::to_string(size) + " is past the end");
  const nlohmann::json header =
      parse_json(std::string_view(data).substr(sizeof size, size), "the header of " + path.string());
  if (!header.is_object()) throw fail("the header is not a JSON object");
  const std::uint64_t bytes = data.size() - sizeof size - size;
  SafeTensors file;
  struct Span {
    std::uint64_t begin, end;
    std::size_t index;
  };
  std::vector<Span> spans;
  try {
    for (const auto& [name, entry] : header.items()) {
      if (name == "__metadata__") {
        for (const auto& [key, value] : entry.items()) file.metadata[key] = value.get<std::string>();
        continue;
      }
      if (entry.at("dtype").get<std::string>() != "F32") throw fail("tensor '" + name + "' is not F32");
      SafeTensor t{name, entry.at("shape").get<std::vector<std::uint64_t>>(), {}};
      const auto offsets = entry.at("data_offsets").get<std::vector<std::uint64_t>>();
      // Bounded as it is formed: a hostile shape's product would wrap around and pass the size check.
      std::uint64_t count = 1;
      for (const auto d : t.shape)
        if (d != 0 && count > bytes / sizeof(float) / d)
          throw fail("tensor '" + name + "': shape exceeds the file");
        else
          count *= d;
      if (offsets.size() != 2 || offsets[0] > offsets[1] || offsets[1] > bytes ||
          offsets[1] - offsets[0] != count * sizeof(float))
        throw fail("tensor '" + name + "': data_offsets do not match its shape or the file");
      t.values.resize(product(t.shape));
      if (!t.values.empty())
        std::memcpy(t.values.data(), data.data() + sizeof size + size + offsets[0], offsets[1] - offsets[0]);
      spans.push_back({offsets[0], offsets[1], file.tensors.size()});
      file.tensors.push_back(std::move(t));
    }
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("malformed header entry (") + clip(e.what()) + ")");
  }
  // The format's rule: the data is covered exactly, without holes or overlaps.
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.begin < b.begin; });
  std::uint64_t at = 0;
  for (const auto& s : spans) {
    if (s.begin != at) throw fail("tensor data overlaps or leaves a hole at byte " + std::to_string(at));
    at = s.end;
  }
  if (at != bytes) throw fail("trailing bytes after the last tensor");
  std::vector<SafeTensor> ordered;
  for (const auto& s : spans) ordered.push_back(std::move(file.tensors[s.index]));
  file.tensors = std::move(ordered);
  return file;
}

}  // namespace clr::nn
