#pragma once
// Mitsuba 3's `sdfgrid` shape: a signed distance function sampled on a grid (read from a .vol file), whose surface
// is the zero level set of the grid's trilinear interpolant, negative inside. The grid spans the unit cube [0,1]³
// of object space with its outermost samples on the cube's faces: sample (i, j, k) of an nx × ny × nz grid lies at
// (i/(nx−1), j/(ny−1), k/(nz−1)). clradiosity meshes that surface at load time (see sdf_mesh.cpp).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/mesh.hpp"

namespace clr::scene {

// Mitsuba's grid-based volume data (.vol): values with x fastest, then y, then z, and the channels of one sample
// adjacent.
struct VolumeGrid {
  glm::ivec3 size{0};
  int channels = 0;
  std::vector<float> values;

  // The value at sample (x, y, z) of a single-channel grid.
  float at(int x, int y, int z) const {
    return values[(std::size_t(z) * std::size_t(size.y) + std::size_t(y)) * std::size_t(size.x) + std::size_t(x)];
  }
};

// Grids with more samples along an axis are refused: their mesh would hold hundreds of millions of triangles.
inline constexpr int kMaxVolumeResolution = 512;

// The .vol layout: "VOL", version byte 3, int32 encoding (1: float32, the only one Mitsuba 3 reads), int32 xres,
// yres, zres and channels, a bounding box of 6 float32 (unused: Mitsuba places its grids by to_world), then the
// values. InputError naming the file for a wrong magic, version or encoding, a resolution below 2 or above
// kMaxVolumeResolution along an axis, a file shorter than its header announces, or a non-finite value.
VolumeGrid load_vol(const std::filesystem::path& path);

// Mitsuba's `normals` property: `smooth` (its default) blends the normalised gradients of the eight voxels around
// the nearest grid sample (Hansson-Söderlund et al. 2022), continuous across voxels; `analytic` is the normalised
// gradient of the trilinear interpolant itself, which jumps at voxel faces.
enum class SdfNormals { smooth, analytic };

// Each grid cell is split `subdivision` times per axis for meshing; sdf_mesh.cpp gives the error this leaves. By
// default 4, fewer where the lattice would pass kSdfLattice points along an axis (a 512-sample grid gets 2): the
// error relative to the grid's extent stays below the 40-sample corpus grid's at 4.
inline constexpr int kSdfSubdivision = 4, kSdfLattice = 1024;
// The mesh's triangle budget: a surface that needs more (a noise grid crosses zero in every cell, up to 768
// triangles a cell at 4 splits) is refused before its mesh exhausts memory.
inline constexpr std::size_t kMaxSdfTriangles = std::size_t(1) << 24;

// The zero level set of a single-channel grid's trilinear interpolant as a welded, closed (where the surface does
// not leave the grid) triangle mesh in [0,1]³, wound and shaded with normals pointing to positive values. InputError
// prefixed with `what` when the grid has more than one channel, no zero crossing, or a surface of more than
// `max_triangles` triangles. `subdivision` 0 chooses as above.
Mesh mesh_sdf_grid(const VolumeGrid& grid, SdfNormals normals, const std::string& what, int subdivision = 0,
                   std::size_t max_triangles = kMaxSdfTriangles);

}  // namespace clr::scene
