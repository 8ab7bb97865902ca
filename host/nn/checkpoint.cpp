#include "nn/checkpoint.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr::nn {
namespace {

constexpr char kMagic[8] = {'C', 'L', 'R', 'C', 'K', 'P', 'T', '\n'};
constexpr std::size_t kHeader = 32;

template <typename T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}
void put_str(std::string& out, const std::string& s) {
  put<std::uint64_t>(out, s.size());
  out += s;
}

// Reads the payload with bounds checks: every read past the end is reported as truncation.
struct Reader {
  const std::string& path;
  const char* p;
  const char* end;
  [[noreturn]] void fail(const std::string& what) const { throw InputError("checkpoint " + path + ": " + what); }
  void need(std::uint64_t n, const char* what) const {
    if (std::uint64_t(end - p) < n) fail(std::string("truncated payload while reading ") + what);
  }
  template <typename T>
  T get(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, p, sizeof(T));
    p += sizeof(T);
    return v;
  }
  std::string get_str(const char* what) {
    const auto n = get<std::uint64_t>(what);
    need(n, what);
    std::string s(p, p + n);
    p += n;
    return s;
  }
};

}  // namespace

std::uint64_t fnv1a64(const void* data, std::size_t n) {
  std::uint64_t h = 14695981039346656037ull;
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

const std::vector<float>& Checkpoint::tensor(const std::string& path, const std::string& name,
                                             std::size_t count) const {
  for (const auto& [n, v] : tensors) {
    if (n != name) continue;
    if (v.size() != count)
      throw InputError("checkpoint " + path + ": tensor '" + name + "' holds " + std::to_string(v.size()) +
                       " values, this network needs " + std::to_string(count));
    // A diverged run's weights (or a damaged file whose checksum was rewritten) must not be rendered from, nor be
    // the base of a report: every output of such a model would be NaN, and resuming would train on from it.
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw InputError("checkpoint " + path + ": tensor '" + name + "' holds a non-finite value (" +
                         std::to_string(v[i]) + " at index " + std::to_string(i) +
                         "): the model diverged or the file is damaged");
    return v;
  }
  throw InputError("checkpoint " + path + ": tensor '" + name + "' is missing");
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  std::string payload;
  put_str(payload, c.config_json);
  put<std::uint64_t>(payload, c.step);
  put_str(payload, c.rng_state);
  put<std::uint32_t>(payload, std::uint32_t(c.tensors.size()));
  for (const auto& [name, values] : c.tensors) {
    put_str(payload, name);
    put<std::uint64_t>(payload, values.size());
    payload.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
  }
  std::string header(kMagic, sizeof(kMagic));
  put<std::uint32_t>(header, kCheckpointVersion);
  put<std::uint32_t>(header, 0);
  put<std::uint64_t>(header, payload.size());
  put<std::uint64_t>(header, fnv1a64(payload.data(), payload.size()));

  require_file_target(path, "checkpoint");
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(header.data(), std::streamsize(header.size()));
    out.write(payload.data(), std::streamsize(payload.size()));
    out.close();
    if (!out) throw std::runtime_error("writing checkpoint " + path + " failed (disk full?)");
  });
}

Checkpoint read_checkpoint(const std::string& path) {
  const std::string data = read_input_text(path, "checkpoint");
  if (data.size() < kHeader)
    throw InputError("checkpoint " + path + ": truncated header (" + std::to_string(data.size()) + " bytes)");
  if (std::memcmp(data.data(), kMagic, sizeof(kMagic)) != 0)
    throw InputError("checkpoint " + path + ": not a clradiosity checkpoint (bad magic)");
  Reader h{path, data.data() + 8, data.data() + kHeader};
  const auto version = h.get<std::uint32_t>("version");
  h.get<std::uint32_t>("reserved");
  const auto size = h.get<std::uint64_t>("payload size");
  const auto sum = h.get<std::uint64_t>("checksum");
  if (version != kCheckpointVersion)
    throw InputError("checkpoint " + path + ": format version " + std::to_string(version) + ", this build reads " +
                     std::to_string(kCheckpointVersion));
  if (data.size() - kHeader != size)
    throw InputError("checkpoint " + path + ": payload is " + std::to_string(data.size() - kHeader) +
                     " bytes, the header says " + std::to_string(size) + " (truncated or appended to)");
  if (fnv1a64(data.data() + kHeader, size) != sum)
    throw InputError("checkpoint " + path + ": checksum mismatch (the file is corrupt)");
  Reader r{path, data.data() + kHeader, data.data() + data.size()};
  Checkpoint c;
  c.config_json = r.get_str("config");
  c.step = r.get<std::uint64_t>("step");
  c.rng_state = r.get_str("rng state");
  const auto n = r.get<std::uint32_t>("tensor count");
  std::set<std::string> names;
  for (std::uint32_t i = 0; i < n; ++i) {
    auto name = r.get_str("tensor name");
    // One tensor per name: with two, which one a reader takes would depend on the reader (and an export would
    // write both under one key).
    if (!names.insert(name).second) r.fail("tensor '" + clip(name) + "' appears twice");
    const auto count = r.get<std::uint64_t>("tensor size");
    // Divided, not multiplied: count · 4 wraps around for a hostile count and would pass the check.
    if (count > std::uint64_t(r.end - r.p) / sizeof(float)) r.fail("truncated payload while reading tensor values");
    std::vector<float> v(count);
    if (count) std::memcpy(v.data(), r.p, count * sizeof(float));  // an empty vector's data() may be null
    r.p += count * sizeof(float);
    c.tensors.emplace_back(std::move(name), std::move(v));
  }
  if (r.p != r.end) r.fail("trailing bytes after the last tensor");
  return c;
}

}  // namespace clr::nn
