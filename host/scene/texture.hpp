#pragma once
// Spatially varying reflectances: a constant, a bitmap or a checkerboard (Mitsuba's `bitmap`, `checkerboard`).
// A constant costs one branch and no memory beyond its colour, so untextured scenes pay nothing for textures.
#include <filesystem>
#include <memory>
#include <vector>

#include "scene/frame.hpp"

namespace clr::scene {

// Texels in linear RGB, row 0 at v = 0 (Mitsuba's convention: mesh loaders flip v so that images appear upright).
struct Bitmap {
  // Texel addressing outside [0, 1)² (Mitsuba's wrap_mode).
  enum class Wrap { repeat, mirror, clamp };
  int width = 0, height = 0;
  std::vector<Rgb> texels;
  Rgb mean{0.0f};

  // png/jpg/bmp (8-bit; sRGB-decoded unless `raw`, or decoded as value^gamma when `gamma` > 0, Mitsuba 0.x's
  // override) or exr/hdr (linear). InputError naming the file on failure.
  static std::shared_ptr<const Bitmap> load(const std::filesystem::path& path, bool raw, float gamma = 0);
  Rgb texel(int x, int y, Wrap wrap = Wrap::repeat) const;
  Rgb bilinear(const Vec2& uv, Wrap wrap = Wrap::repeat) const;  // texel centres at half-integers
  Rgb nearest(const Vec2& uv, Wrap wrap = Wrap::repeat) const;
};

// 2-D affine map applied to uv before lookup (Mitsuba's `to_uv`): uv' = linear · uv + offset.
struct UvTransform {
  glm::mat2 linear{1.0f};
  Vec2 offset{0.0f};
  Vec2 apply(const Vec2& uv) const { return linear * uv + offset; }
};

class Texture {
 public:
  enum class Kind { constant, bitmap, checkerboard };

  Texture(const Rgb& value = Rgb(0.0f)) : kind_(Kind::constant), c0_(value) {}  // NOLINT: a colour is a texture
  static Texture bitmap(std::shared_ptr<const Bitmap> bitmap, const UvTransform& to_uv, bool bilinear,
                        Bitmap::Wrap wrap = Bitmap::Wrap::repeat);
  static Texture checkerboard(const Rgb& color0, const Rgb& color1, const UvTransform& to_uv);

  Rgb eval(const Vec2& uv) const {
    if (kind_ == Kind::constant) return c0_;
    return eval_varying(uv);
  }
  bool is_constant() const { return kind_ == Kind::constant; }
  Kind kind() const { return kind_; }
  // Average over the texture (exact for constants and checkerboards, texel mean for bitmaps): used where a single
  // colour is needed, e.g. for lobe-selection weights.
  Rgb mean() const;
  // Texels along u and v: a bitmap's size, (1, 1) for the others (Mitsuba's `resolution`).
  glm::ivec2 resolution() const {
    return kind_ == Kind::bitmap ? glm::ivec2(bitmap_->width, bitmap_->height) : glm::ivec2(1);
  }

 private:
  Rgb eval_varying(const Vec2& uv) const;

  Kind kind_;
  Rgb c0_, c1_{0.0f};
  std::shared_ptr<const Bitmap> bitmap_;
  UvTransform to_uv_;
  bool bilinear_ = true;
  Bitmap::Wrap wrap_ = Bitmap::Wrap::repeat;
};

}  // namespace clr::scene
