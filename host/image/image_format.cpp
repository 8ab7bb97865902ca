#include "image/image_format.hpp"

#include <algorithm>
#include <cctype>
#include <system_error>

#include "common/error.hpp"

namespace clr::image {
namespace fs = std::filesystem;

namespace {

const char* extension_of(Format f) { return f == Format::Exr ? ".exr" : ".png"; }

}  // namespace

Format output_format(const fs::path& path, const std::string& option, std::initializer_list<Format> allowed) {
  if (path.empty()) return *allowed.begin();
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status)) return *allowed.begin();
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  std::string names;
  for (const Format f : allowed) {
    if (ext == extension_of(f)) return f;
    names += std::string(names.empty() ? "" : " or ") + extension_of(f);
  }
  throw InputError(option + " " + path.string() + ": the extension names the image format; use " + names +
                   (ext.empty() ? "" : " (not " + ext + ")"));
}

void write_image(const fs::path& path, const Image& img, Format format,
                 const std::map<std::string, std::string>& attributes) {
  if (format == Format::Exr)
    write_exr(path, img, attributes);
  else
    write_png(path, img);
}

}  // namespace clr::image
