#include "scene/environment.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "image/image.hpp"

namespace clr::scene {
namespace {
// Index i with cdf[i] <= u < cdf[i+1] and the position of u within it.
std::pair<int, float> sample_cdf(const float* cdf, int n, float u) {
  const int i = std::clamp(int(std::upper_bound(cdf, cdf + n + 1, u) - cdf) - 1, 0, n - 1);
  const float width = cdf[i + 1] - cdf[i];
  return {i, width > 0 ? std::clamp((u - cdf[i]) / width, 0.0f, 1.0f) : 0.5f};
}
}  // namespace

Environment Environment::constant(const Rgb& radiance) {
  Environment e;
  e.constant_ = radiance;
  return e;
}

void Environment::set_to_world(const glm::mat4& to_world) {
  to_world_ = glm::mat3(to_world);
  to_local_ = glm::inverse(to_world_);
  jacobian_scale_ = std::fabs(glm::determinant(to_local_));
}

Environment Environment::envmap(const std::filesystem::path& path, float scale, const glm::mat4& to_world) {
  if (!std::filesystem::exists(path)) throw InputError(path.string() + ": environment map not found");
  const image::Image img = image::read_float_image(path);
  Environment e;
  e.width_ = img.width;
  e.height_ = img.height;
  e.set_to_world(to_world);
  e.pixels_.resize(std::size_t(img.width) * std::size_t(img.height));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(img.width) + std::size_t(x);
      const Rgb c = scale * Rgb(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
        throw InputError(path.string() + ": environment map has non-finite pixels");
      if (!(c.x >= 0 && c.y >= 0 && c.z >= 0))
        throw InputError(path.string() + ": environment map has a negative pixel at (" + std::to_string(x) + ", " +
                         std::to_string(y) + ")");
      e.pixels_[i] = c;
    }
  // A table cell's weight: the brightest texel whose bilinear support reaches into it (rows at v = i / (H − 1),
  // columns at u = (j + ½) / W; lookup() below), so the density is never zero where the radiance is not.
  const int W = e.width_, H = e.height_;
  std::vector<float> cell(e.pixels_.size(), 0.0f);
  for (int y = 0; y < H; ++y) {
    const float t0 = float(y) * float(H - 1) / float(H), t1 = float(y + 1) * float(H - 1) / float(H);
    const int r0 = std::max(0, int(std::floor(t0))), r1 = std::min(H - 1, int(std::ceil(t1)));
    for (int x = 0; x < W; ++x) {
      float most = 0;
      for (int r = r0; r <= r1; ++r)
        for (int dx = -1; dx <= 1; ++dx)
          most = std::fmax(most, luminance(e.pixels_[std::size_t(r) * std::size_t(W) + std::size_t((x + dx + W) % W)]));
      cell[std::size_t(y) * std::size_t(W) + std::size_t(x)] = most;
    }
  }
  if (!(e.build_table(cell) > 0)) throw InputError(path.string() + ": environment map is black");
  return e;
}

Environment Environment::sunsky(const SunSky& model, const glm::mat4& to_world) {
  Environment e;
  e.set_to_world(to_world);
  e.sunsky_ = std::make_shared<const SunSky>(model);
  // The sky tabulated at texel centres for sampling only (eval is analytic): 0.35° texels hold the circumsolar peak.
  e.width_ = 1024;
  e.height_ = 512;
  e.pixels_.resize(std::size_t(e.width_) * std::size_t(e.height_));
  for (int y = 0; y < e.height_; ++y)
    for (int x = 0; x < e.width_; ++x) {
      const float phi = 2.0f * kPi * (float(x) + 0.5f) / float(e.width_),
                  theta = kPi * (float(y) + 0.5f) / float(e.height_);
      const Vec3 local(std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta));
      e.pixels_[std::size_t(y) * std::size_t(e.width_) + std::size_t(x)] = model.sky(local);
    }
  // The sun's share of the draws: its power against the sky's (luminance over solid angle; a texel spans
  // 2π/width · π/height in φ and θ, times sin θ, which the table's weights hold).
  std::vector<float> sky_luminance(e.pixels_.size());
  for (std::size_t i = 0; i < e.pixels_.size(); ++i) sky_luminance[i] = luminance(e.pixels_[i]);
  const double sky = e.build_table(sky_luminance) * (2 * M_PI / e.width_) * (M_PI / e.height_);
  const double sun = luminance(model.sun_radiance()) * model.sun_solid_angle();
  e.sun_probability_ = !(sky > 0) ? 1.0f : float(sun / (sun + sky));
  return e;
}

double Environment::build_table(const std::vector<float>& cell_luminance) {
  weights_.resize(pixels_.size());
  double total = 0;
  for (int y = 0; y < height_; ++y) {
    const float sin_theta = std::sin(kPi * (float(y) + 0.5f) / float(height_));
    for (int x = 0; x < width_; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(width_) + std::size_t(x);
      weights_[i] = std::fmax(cell_luminance[i], 0.0f) * sin_theta;
      total += weights_[i];
    }
  }
  if (!(total > 0)) return 0;
  const double mean = total / double(weights_.size());
  for (auto& w : weights_) w = float(w / mean);
  row_cdf_.assign(std::size_t(height_) + 1, 0.0f);
  column_cdf_.assign(std::size_t(height_) * std::size_t(width_ + 1), 0.0f);
  double rows = 0;
  std::vector<double> row_sum(std::size_t(height_), 0.0);
  for (int y = 0; y < height_; ++y) {
    float* cdf = &column_cdf_[std::size_t(y) * std::size_t(width_ + 1)];
    double s = 0;
    for (int x = 0; x < width_; ++x) {
      s += weights_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
      cdf[x + 1] = float(s);
    }
    for (int x = 1; x <= width_; ++x) cdf[x] = s > 0 ? float(cdf[x] / s) : float(x) / float(width_);
    rows += s;
    row_sum[std::size_t(y)] = rows;
  }
  for (int y = 0; y < height_; ++y) row_cdf_[std::size_t(y) + 1] = float(row_sum[std::size_t(y)] / rows);
  row_cdf_.back() = 1.0f;
  return total;
}

// Mitsuba's lat-long mapping: u = atan2(x, −z)/2π, v = acos(y)/π in the emitter's local frame, v = 0 the top row.
Vec2 Environment::to_uv(const Vec3& d) const {
  float u = std::atan2(d.x, -d.z) / (2.0f * kPi);
  if (u < 0) u += 1.0f;
  return {u, std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi};
}

float Environment::pixel_pdf(int x, int y) const {
  return weights_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];  // mean-normalised: a density in uv
}

// Mitsuba 3's envmap convention (checked against its own eval): texel column j at u = (j + ½) / W, wrapping
// around, and texel row i at v = i / (H − 1), the first and last rows on the poles.
Rgb Environment::lookup(const Vec2& uv) const {
  const float x = uv.x * float(width_) - 0.5f, y = uv.y * float(height_ - 1);
  const float x_floor = std::floor(x), y_floor = std::floor(y), ax = x - x_floor, ay = y - y_floor;
  const int x0 = ((int(x_floor) % width_) + width_) % width_, x1 = (x0 + 1) % width_;
  const int y0 = std::clamp(int(y_floor), 0, height_ - 1), y1 = std::clamp(int(y_floor) + 1, 0, height_ - 1);
  const auto at = [&](int px, int py) { return pixels_[std::size_t(py) * std::size_t(width_) + std::size_t(px)]; };
  return (1.0f - ay) * ((1.0f - ax) * at(x0, y0) + ax * at(x1, y0)) + ay * ((1.0f - ax) * at(x0, y1) + ax * at(x1, y1));
}

Rgb Environment::eval(const Vec3& dir, bool sun) const {
  if (sunsky_) {
    const Vec3 local = glm::normalize(to_local_ * dir);
    return sun ? sunsky_->sky(local) + sunsky_->sun(local) : sunsky_->sky(local);
  }
  if (width_ == 0) return constant_;
  return lookup(to_uv(glm::normalize(to_local_ * dir)));
}

std::optional<DeltaLight> Environment::sun_as_directional() const {
  if (!sunsky_ || is_black(sunsky_->sun_radiance()) || sunsky_->parameters().sun.z < 0) return std::nullopt;
  DeltaLight l;
  l.kind = DeltaLight::Kind::directional;
  l.direction = -glm::normalize(to_world_ * sunsky_->parameters().sun);
  l.intensity = sunsky_->sun_radiance() * float(sunsky_->sun_solid_angle());
  return l;
}

Environment::Sample Environment::sample(const Vec2& u) const {
  if (sunsky_) {
    Vec3 d;
    if (u.x < sun_probability_) {
      d = glm::normalize(to_world_ * sunsky_->sample_sun(Vec2(u.x / sun_probability_, u.y)));
    } else {
      d = sample_table(Vec2((u.x - sun_probability_) / (1.0f - sun_probability_), u.y)).dir;
    }
    return {d, eval(d), pdf(d)};
  }
  if (width_ == 0) {
    const Vec3 d = sample_uniform_sphere(u);
    return {d, constant_, kUniformSpherePdf};
  }
  return sample_table(u);
}

Environment::Sample Environment::sample_table(const Vec2& u) const {
  const auto [y, fy] = sample_cdf(row_cdf_.data(), height_, u.y);
  const auto [x, fx] = sample_cdf(&column_cdf_[std::size_t(y) * std::size_t(width_ + 1)], width_, u.x);
  const float su = (float(x) + fx) / float(width_), sv = (float(y) + fy) / float(height_);
  const float phi = 2.0f * kPi * su, theta = kPi * sv;
  const float sin_theta = std::sin(theta);
  const Vec3 local(std::sin(phi) * sin_theta, std::cos(theta), -std::cos(phi) * sin_theta);
  const Vec3 stretched = to_world_ * local;
  const float length = glm::length(stretched);
  const Vec3 d = stretched / length;
  // |dω_local/dω_world| = |det to_local| · |to_world · local|³ (1 for a rotation).
  const float pdf = sin_theta > 0
                        ? pixel_pdf(x, y) / (2.0f * kPi * kPi * sin_theta) * jacobian_scale_ * length * length * length
                        : 0.0f;
  return {d, lookup(Vec2(su, sv)), pdf};
}

float Environment::pdf(const Vec3& dir) const {
  if (sunsky_) {
    float p = sun_probability_ < 1 ? (1.0f - sun_probability_) * pdf_table(dir) : 0.0f;
    const Vec3 stretched = to_local_ * glm::normalize(dir);
    const float length = glm::length(stretched);
    if (sun_probability_ > 0 && sunsky_->in_sun(stretched / length))
      p += float(double(sun_probability_) / sunsky_->sun_solid_angle()) * jacobian_scale_ / (length * length * length);
    return p;
  }
  if (width_ == 0) return kUniformSpherePdf;
  return pdf_table(dir);
}

float Environment::pdf_table(const Vec3& dir) const {
  const Vec3 stretched = to_local_ * glm::normalize(dir);
  const float length = glm::length(stretched);
  const Vec3 local = stretched / length;
  const Vec2 uv = to_uv(local);
  const float sin_theta = std::sqrt(std::fmax(0.0f, 1.0f - local.y * local.y));
  if (!(sin_theta > 0)) return 0.0f;
  const int x = std::min(int(uv.x * float(width_)), width_ - 1), y = std::min(int(uv.y * float(height_)), height_ - 1);
  // |dω_local/dω_world| = |det to_local| / |to_local · dir|³ (1 for a rotation).
  return pixel_pdf(x, y) / (2.0f * kPi * kPi * sin_theta) * jacobian_scale_ / (length * length * length);
}

}  // namespace clr::scene
