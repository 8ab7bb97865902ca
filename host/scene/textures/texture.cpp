#include "scene/texture.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/packing.hpp>
#include <limits>

#include "common/error.hpp"
#include "image/image.hpp"
#include "scene/mesh.hpp"

namespace clr::scene {
namespace {
int repeat(int i, int n) {
  const int m = i % n;
  return m < 0 ? m + n : m;
}
int address(int i, int n, Bitmap::Wrap wrap) {
  switch (wrap) {
    case Bitmap::Wrap::clamp:
      return std::clamp(i, 0, n - 1);
    case Bitmap::Wrap::mirror: {
      const int m = repeat(i, 2 * n);
      return m < n ? m : 2 * n - 1 - m;
    }
    default:
      return repeat(i, n);
  }
}
}  // namespace

std::shared_ptr<const Bitmap> Bitmap::load(const std::filesystem::path& path, bool raw, float gamma, Storage storage) {
  if (!std::filesystem::exists(path)) throw InputError(path.string() + ": texture file not found");
  auto ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  // EXR stores linear values already; 8-bit formats are sRGB-encoded unless the scene says `raw`.
  const bool hdr = ext == ".exr" || ext == ".hdr";
  image::Image img = hdr ? image::read_float_image(path) : image::read_ldr(path, !raw && !(gamma > 0));
  if (!hdr && !raw && gamma > 0)
    for (float& v : img.rgb) v = std::pow(v, gamma);
  if (storage == Storage::float16)
    for (float& v : img.rgb) v = glm::unpackHalf1x16(glm::packHalf1x16(v));
  if (storage == Storage::uint8 && hdr)
    for (float& v : img.rgb)  // Mitsuba's float → byte conversion: ⌊256·v⌋, clamped to the byte's range
      v = std::fmin(std::floor(std::clamp(v, 0.0f, 1.0f) * 256.0f), 255.0f) / 255.0f;
  auto bmp = std::make_shared<Bitmap>();
  bmp->width = img.width;
  bmp->height = img.height;
  bmp->texels.resize(std::size_t(img.width) * std::size_t(img.height));
  glm::dvec3 sum(0.0);
  bmp->minimum = Rgb(std::numeric_limits<float>::infinity());
  bmp->maximum = Rgb(-std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < bmp->texels.size(); ++i) {
    bmp->texels[i] = Rgb(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
    // An EXR may hold NaN or infinities; as a reflectance they would poison every path that touches them.
    if (!std::isfinite(bmp->texels[i].x) || !std::isfinite(bmp->texels[i].y) || !std::isfinite(bmp->texels[i].z))
      throw InputError(path.string() + ": texture has non-finite texels");
    sum += glm::dvec3(bmp->texels[i]);
    bmp->minimum = glm::min(bmp->minimum, bmp->texels[i]);
    bmp->maximum = glm::max(bmp->maximum, bmp->texels[i]);
  }
  if (bmp->texels.empty()) throw InputError(path.string() + ": empty texture");
  bmp->mean = Rgb(sum / double(bmp->texels.size()));
  return bmp;
}

Rgb Bitmap::texel(int x, int y, Wrap wrap) const {
  return texels[std::size_t(address(y, height, wrap)) * width + address(x, width, wrap)];
}

Rgb Bitmap::bilinear(const Vec2& uv, Wrap wrap) const {
  const float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  const int ix = int(fx), iy = int(fy);
  return (1 - ay) * ((1 - ax) * texel(ix, iy, wrap) + ax * texel(ix + 1, iy, wrap)) +
         ay * ((1 - ax) * texel(ix, iy + 1, wrap) + ax * texel(ix + 1, iy + 1, wrap));
}

Rgb Bitmap::nearest(const Vec2& uv, Wrap wrap) const {
  return texel(int(std::floor(uv.x * float(width))), int(std::floor(uv.y * float(height))), wrap);
}

Texture Texture::bitmap(std::shared_ptr<const Bitmap> bitmap, const UvTransform& to_uv, bool bilinear,
                        Bitmap::Wrap wrap) {
  Texture t;
  t.kind_ = Kind::bitmap;
  t.bitmap_ = std::move(bitmap);
  t.to_uv_ = to_uv;
  t.bilinear_ = bilinear;
  t.wrap_ = wrap;
  return t;
}

Texture Texture::checkerboard(const Rgb& color0, const Rgb& color1, const UvTransform& to_uv) {
  Texture t(color0);
  t.kind_ = Kind::checkerboard;
  t.c1_ = color1;
  t.to_uv_ = to_uv;
  return t;
}

Texture Texture::mesh_attribute(const std::string& name, float scale, const std::string& id) {
  Texture t{Rgb(scale)};  // c0_ holds the scale
  t.kind_ = Kind::mesh_attribute;
  t.attribute_ = name;
  t.id_ = id;
  return t;
}

Rgb Texture::eval_varying(const TexturePoint& at) const {
  if (kind_ == Kind::mesh_attribute) {
    // The loader refuses a shape whose material names an attribute its mesh lacks; only a point without a mesh
    // (a bare uv) finds none, and sees black.
    const MeshAttribute* a = at.mesh ? at.mesh->attribute(attribute_) : nullptr;
    return a ? c0_ * a->eval(at.prim, at.mesh->triangles[at.prim], at.barycentric) : Rgb(0.0f);
  }
  if (kind_ == Kind::bitmap) {
    const Vec2 uv = to_uv_.apply(at.uv);
    return bilinear_ ? bitmap_->bilinear(uv, wrap_) : bitmap_->nearest(uv, wrap_);
  }
  // Mitsuba's checkerboard: colour 0 where the fractional parts of u and v lie in the same half.
  return in_same_halves(at) ? c0_ : c1_;
}

bool Texture::in_same_halves(const TexturePoint& at) const {
  const Vec2 uv = to_uv_.apply(at.uv);
  return (uv.x - std::floor(uv.x) > 0.5f) == (uv.y - std::floor(uv.y) > 0.5f);
}

namespace {
// A grey is its value exactly, as Mitsuba's `uniform` texture (a float) returns it; (3v)/3 can round off it.
float channel_mean(const Rgb& c) { return c.x == c.y && c.y == c.z ? c.x : (c.x + c.y + c.z) / 3.0f; }
}  // namespace

float Texture::eval_1(const TexturePoint& at) const {
  switch (kind_) {
    case Kind::constant:
      return channel_mean(c0_);
    case Kind::bitmap:
      return luminance(eval_varying(at));
    case Kind::checkerboard:
      return channel_mean(in_same_halves(at) ? c1_ : c0_);
    case Kind::mesh_attribute:
      return eval_varying(at).x;
  }
  return channel_mean(c0_);
}

float Texture::mean_1() const { return kind_ == Kind::bitmap ? luminance(bitmap_->mean) : channel_mean(mean()); }

float Texture::texel_uv() const {
  if (kind_ != Kind::bitmap) return std::numeric_limits<float>::infinity();
  const float stretch = std::max(glm::length(to_uv_.linear[0]), glm::length(to_uv_.linear[1]));
  return 1.0f / (float(std::max(bitmap_->width, bitmap_->height)) * std::max(stretch, 1e-30f));
}

Rgb Texture::mean() const {
  switch (kind_) {
    case Kind::constant:
      return c0_;
    case Kind::bitmap:
      return bitmap_->mean;
    case Kind::checkerboard:
      return 0.5f * (c0_ + c1_);
    case Kind::mesh_attribute:
      return 0.5f * c0_;
  }
  return c0_;
}

Rgb Texture::maximum() const {
  switch (kind_) {
    case Kind::constant:
      return c0_;
    case Kind::bitmap:
      return bitmap_->maximum;
    case Kind::checkerboard:
      return glm::max(c0_, c1_);
    case Kind::mesh_attribute:
      return Rgb(std::numeric_limits<float>::infinity());
  }
  return c0_;
}

Rgb Texture::minimum() const {
  switch (kind_) {
    case Kind::constant:
      return c0_;
    case Kind::bitmap:
      return bitmap_->minimum;
    case Kind::checkerboard:
      return glm::min(c0_, c1_);
    case Kind::mesh_attribute:
      return glm::min(c0_, Rgb(0.0f));
  }
  return c0_;
}

}  // namespace clr::scene
