#pragma once
// Spatially varying reflectances: a constant, a bitmap, a checkerboard or a mesh attribute (Mitsuba's `bitmap`,
// `checkerboard`, `mesh_attribute`). A constant costs one branch and no memory beyond its colour, so untextured
// scenes pay nothing for textures.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scene/frame.hpp"

namespace clr::scene {

// Texels in linear RGB, row 0 at v = 0 (Mitsuba's convention: mesh loaders flip v so that images appear upright).
struct Bitmap {
  // Texel addressing outside [0, 1)² (Mitsuba's wrap_mode).
  enum class Wrap { repeat, mirror, clamp };
  // Mitsuba 3's `format`, the precision texels are stored at: as read (auto, variant), rounded to half floats, or
  // to 8 bits (linear values clamped to [0, 1] and quantised as Mitsuba does; an 8-bit file is stored so already).
  enum class Storage { full, float16, uint8 };
  int width = 0, height = 0;
  std::vector<Rgb> texels;
  Rgb mean{0.0f};
  Rgb minimum{0.0f};  // per channel over the texels
  Rgb maximum{0.0f};

  // png/jpg/bmp (8-bit; sRGB-decoded unless `raw`, or decoded as value^gamma when `gamma` > 0, Mitsuba 0.x's
  // override) or exr/hdr (linear). InputError naming the file on failure.
  static std::shared_ptr<const Bitmap> load(const std::filesystem::path& path, bool raw, float gamma = 0,
                                            Storage storage = Storage::full);
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

struct Mesh;

// Where a texture is looked up: the surface's uv and, for mesh attributes, the triangle hit on its mesh and the
// barycentrics there (Mitsuba's SurfaceInteraction, as much of it as textures read). A bare uv (an emitter's
// projection, a test) has no mesh.
struct TexturePoint {
  Vec2 uv{0.0f};
  const Mesh* mesh = nullptr;
  std::uint32_t prim = 0;
  Vec2 barycentric{0.0f};  // weights of the triangle's vertices 1 and 2

  TexturePoint(const Vec2& at_uv = Vec2(0.0f)) : uv(at_uv) {}  // NOLINT: a uv is a point without a mesh
  TexturePoint(const Vec2& at_uv, const Mesh& on, std::uint32_t triangle, const Vec2& b)
      : uv(at_uv), mesh(&on), prim(triangle), barycentric(b) {}
};

class Texture {
 public:
  enum class Kind { constant, bitmap, checkerboard, mesh_attribute };

  Texture(const Rgb& value = Rgb(0.0f)) : kind_(Kind::constant), c0_(value) {}  // NOLINT: a colour is a texture
  static Texture bitmap(std::shared_ptr<const Bitmap> bitmap, const UvTransform& to_uv, bool bilinear,
                        Bitmap::Wrap wrap = Bitmap::Wrap::repeat);
  static Texture checkerboard(const Rgb& color0, const Rgb& color1, const UvTransform& to_uv);
  // The mesh's attribute `name` ("vertex_…" interpolated, "face_…" constant per triangle) times `scale`; one
  // channel is replicated to three. `id` names the texture in messages (its XML id, or where it is written).
  static Texture mesh_attribute(const std::string& name, float scale, const std::string& id);

  Rgb eval(const TexturePoint& at) const {
    if (kind_ == Kind::constant) return c0_;
    return eval_varying(at);
  }
  // The texture read as one number, where a BSDF takes a float (roughness, a blend's weight, a mask's opacity, the
  // principled parameters), as Mitsuba 3's eval_1 reads it: a colour's channel mean, a bitmap's luminance, a mesh
  // attribute's single channel (the loader refuses a three-channel one there, as Mitsuba does), and a checkerboard
  // with its colours the other way round. Mitsuba's checkerboard puts colour 0 where u and v lie in the same half
  // when it returns a colour (eval), but where they lie in different halves when it returns a number (eval_1)
  // (checked against 3.9.1), and its renders follow that.
  float eval_1(const TexturePoint& at) const;
  // The mean of eval_1 over the texture (as mean()).
  float mean_1() const;
  bool is_constant() const { return kind_ == Kind::constant; }
  Kind kind() const { return kind_; }
  // Average over the texture (exact for constants and checkerboards, texel mean for bitmaps): used where a single
  // colour is needed, e.g. for lobe-selection weights. A mesh attribute's average depends on the mesh, which a
  // material shared by shapes does not know: it stands as scale/2, a mid-range value (Mitsuba has no mean for it).
  Rgb mean() const;
  // The smallest value the texture takes, per channel (a mesh attribute's: its scale's sign, with the mesh's
  // values checked where a shape reads them): light and reflectance must be non-negative at every texel, not
  // only on average.
  Rgb minimum() const;
  // The largest, per channel: a parameter with an upper bound (a principled roughness) is checked against it.
  // A mesh attribute's is unknown here (+infinity): its values are clamped where they are read.
  Rgb maximum() const;
  // A mesh_attribute's attribute name and the texture's id; empty for the other kinds.
  const std::string& attribute() const { return attribute_; }
  const std::string& id() const { return id_; }
  // Texels along u and v: a bitmap's size, (1, 1) for the others (Mitsuba's `resolution`).
  glm::ivec2 resolution() const {
    return kind_ == Kind::bitmap ? glm::ivec2(bitmap_->width, bitmap_->height) : glm::ivec2(1);
  }
  // The surface's uv distance across one texel (a bitmap's, through its to_uv): the finest detail the texture
  // holds. Infinity for textures without texels.
  float texel_uv() const;

 private:
  Rgb eval_varying(const TexturePoint& at) const;
  bool in_same_halves(const TexturePoint& at) const;  // a checkerboard's cell: u and v in the same half

  Kind kind_;
  Rgb c0_, c1_{0.0f};
  std::shared_ptr<const Bitmap> bitmap_;
  UvTransform to_uv_;
  bool bilinear_ = true;
  Bitmap::Wrap wrap_ = Bitmap::Wrap::repeat;
  std::string attribute_, id_;
};

}  // namespace clr::scene
