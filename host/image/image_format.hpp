#pragma once
// An image output's format is the one its extension names, as in Mitsuba and pbrt (`-o ref.png` writes a PNG, never
// EXR bytes under a PNG name); any other extension is bad input, refused before the work that would produce it.
#include <filesystem>
#include <initializer_list>
#include <string>

#include "image/image.hpp"

namespace clr::image {

enum class Format { Exr, Png };

// The format of `path`'s extension (.exr or .png, in any case) among `allowed`; InputError "<option> PATH: …"
// naming the extensions allowed otherwise. An existing device or FIFO (`-o /dev/null`) has no extension to read
// and takes the first allowed format. An empty path (the option was not given) is not checked.
Format output_format(const std::filesystem::path& path, const std::string& option,
                     std::initializer_list<Format> allowed = {Format::Exr, Format::Png});

// write_exr with `attributes` in its header, or write_png of the linear image (sRGB, exposure 0; PNG has no room
// for them).
void write_image(const std::filesystem::path& path, const Image& img, Format format,
                 const std::map<std::string, std::string>& attributes = {});

}  // namespace clr::image
