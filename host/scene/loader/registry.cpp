// Mitsuba plugin type → reader, one line per plugin (Mitsuba's plugin factory), and the plugins refused on purpose.
#include <cstring>

#include "scene/loader/plugin.hpp"

namespace clr::scene::loader {

// X(type, reader): the reader is defined in the plugin's own file (bsdfs/<name>.cpp, ...).
#define CLR_BSDF_PLUGINS(X)             \
  X("diffuse", read_diffuse)            \
  X("roughdiffuse", read_roughdiffuse)  \
  X("phong", read_phong)                \
  X("ward", read_ward)                  \
  X("twosided", read_twosided)          \
  X("conductor", read_conductor)        \
  X("roughconductor", read_conductor)   \
  X("plastic", read_plastic)            \
  X("roughplastic", read_plastic)       \
  X("pplastic", read_pplastic)          \
  X("dielectric", read_dielectric)      \
  X("thindielectric", read_dielectric)  \
  X("roughdielectric", read_dielectric) \
  X("mask", read_mask)                  \
  X("bumpmap", read_bumpmap)            \
  X("blendbsdf", read_blendbsdf)        \
  X("null", read_null)                  \
  X("normalmap", read_normalmap)        \
  X("principled", read_principled)      \
  X("principledthin", read_principledthin)

#define CLR_TEXTURE_PLUGINS(X)             \
  X("bitmap", read_bitmap)                 \
  X("checkerboard", read_checkerboard)     \
  X("mesh_attribute", read_mesh_attribute) \
  X("rawconstant", read_rawconstant)

#define CLR_SHAPE_PLUGINS(X)       \
  X("obj", read_obj)               \
  X("ply", read_ply)               \
  X("serialized", read_serialized) \
  X("rectangle", read_rectangle)   \
  X("cube", read_cube)             \
  X("disk", read_disk)             \
  X("sphere", read_sphere)         \
  X("cylinder", read_cylinder)     \
  X("sdfgrid", read_sdfgrid)

#define CLR_EMITTER_PLUGINS(X)       \
  X("area", read_area)               \
  X("constant", read_constant)       \
  X("envmap", read_envmap)           \
  X("sunsky", read_sunsky)           \
  X("point", read_point)             \
  X("spot", read_spot)               \
  X("directional", read_directional) \
  X("projector", read_projector)

#define CLR_SENSOR_PLUGINS(X)        \
  X("perspective", read_perspective) \
  X("thinlens", read_thinlens)       \
  X("orthographic", read_orthographic)

#define CLR_DECLARE_BSDF(type, fn) std::shared_ptr<const Bsdf> fn(Context&, const Props&);
#define CLR_DECLARE_TEXTURE(type, fn) Texture fn(Context&, const Props&);
#define CLR_DECLARE_SHAPE(type, fn) ShapePlugin fn(Context&, const Props&);
#define CLR_DECLARE_EMITTER(type, fn) EmitterPlugin fn(Context&, const Props&);
#define CLR_DECLARE_SENSOR(type, fn) void fn(Context&, const Props&, Camera&);
#define CLR_ENTRY(type, fn) {type, fn},

CLR_BSDF_PLUGINS(CLR_DECLARE_BSDF)
CLR_TEXTURE_PLUGINS(CLR_DECLARE_TEXTURE)
CLR_SHAPE_PLUGINS(CLR_DECLARE_SHAPE)
CLR_EMITTER_PLUGINS(CLR_DECLARE_EMITTER)
CLR_SENSOR_PLUGINS(CLR_DECLARE_SENSOR)

namespace {
template <typename Reader>
Reader find(const std::map<std::string, Reader>& table, const std::string& type) {
  const auto it = table.find(type);
  return it == table.end() ? nullptr : it->second;
}
}  // namespace

BsdfReader bsdf_reader(const std::string& type) {
  static const std::map<std::string, BsdfReader> table{CLR_BSDF_PLUGINS(CLR_ENTRY)};
  return find(table, type);
}
TextureReader texture_reader(const std::string& type) {
  static const std::map<std::string, TextureReader> table{CLR_TEXTURE_PLUGINS(CLR_ENTRY)};
  return find(table, type);
}
ShapeReader shape_reader(const std::string& type) {
  static const std::map<std::string, ShapeReader> table{CLR_SHAPE_PLUGINS(CLR_ENTRY)};
  return find(table, type);
}
EmitterReader emitter_reader(const std::string& type) {
  static const std::map<std::string, EmitterReader> table{CLR_EMITTER_PLUGINS(CLR_ENTRY)};
  return find(table, type);
}
SensorReader sensor_reader(const std::string& type) {
  static const std::map<std::string, SensorReader> table{CLR_SENSOR_PLUGINS(CLR_ENTRY)};
  return find(table, type);
}

const char* refused_plugin(const std::string& kind, const std::string& type) {
  struct Refusal {
    const char *kind, *type, *why;
  };
  static constexpr Refusal kRefused[] = {
      {"shape", "linearcurve", "curves (hair) are not surfaces: radiosity is surface-only"},
      {"shape", "bsplinecurve", "curves (hair) are not surfaces: radiosity is surface-only"},
      {"bsdf", "hair", "hair fibres are curves, not surfaces: radiosity is surface-only"},
      {"bsdf", "polarizer", "polarization is not modelled (radiance is unpolarized RGB)"},
      {"bsdf", "retarder", "polarization is not modelled (radiance is unpolarized RGB)"},
      {"bsdf", "measured_polarized", "polarization is not modelled (radiance is unpolarized RGB)"},
      {"integrator", "stokes", "polarization is not modelled (radiance is unpolarized RGB)"},
      {"emitter", "timed_sunsky",
       "timed_sunsky (a sun averaged over days and hours by each ray's time) is not modelled: use sunsky at one time"},
      {"phase", "*", "participating media are not modelled: radiosity is surface-only"},
      {"medium", "*", "participating media are not modelled: radiosity is surface-only"},
      {"texture", "volume",
       "3D grid textures (volume) are not supported: textures here are 2D (bitmap, checkerboard, mesh_attribute)"},
      {"volume", "*",
       "3D grids (constvolume, gridvolume) are not supported: textures here are 2D (bitmap, checkerboard, "
       "mesh_attribute), and media are not modelled"},
  };
  for (const auto& r : kRefused)
    if (kind == r.kind && (type == r.type || std::strcmp(r.type, "*") == 0)) return r.why;
  return nullptr;
}

}  // namespace clr::scene::loader
