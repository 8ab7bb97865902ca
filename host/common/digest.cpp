#include "common/digest.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace clr {

Digest& Digest::add(std::string_view bytes) {
  for (const char c : bytes) {
    state_ ^= static_cast<unsigned char>(c);
    state_ *= 0x100000001b3ull;
  }
  return *this;
}

Digest& Digest::add_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    add({chunk.data(), std::size_t(in.gcount())});
  }
  if (!in.eof()) throw std::runtime_error("cannot read " + file.string());
  return *this;
}

std::string Digest::hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state_));
  return text;
}

}  // namespace clr
