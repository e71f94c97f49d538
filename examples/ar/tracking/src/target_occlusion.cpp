// The occlusion mask's public API, and the ground its steps work on: the grid of mask pixels (their
// rays, the buffers), where the target lies in it, the frame and the reference read into it, and a
// frame's steps in order (the method: target_occlusion.hpp).
#include "marionette_ar/tracking/target_occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/mat3x3.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/planar_map.hpp"
#include "target_occlusion_impl.hpp"

namespace marionette::ar {

namespace {

constexpr int kCell = 4;  // geometry's first pass: cells of kCell x kCell mask pixels
// With more than this share of the target's blocks clipped, nothing is said hidden.
constexpr double kMaxClippedShare = 0.25;

}  // namespace

std::string OcclusionSettings::problem() const {
  const OcclusionSettings& s = *this;
  if (s.scale < 2 || s.scale > 16) return "scale must be 2..16";
  if (s.window < 3 || s.window > 9 || s.window % 2 == 0) return "window must be odd, 3..9";
  if (s.searchRadius < 0 || s.searchRadius > 3) return "searchRadius must be 0..3";
  if (s.featherPasses < 0 || s.featherPasses > 8) return "featherPasses must be 0..8";
  if (!(s.fineWeight >= 0 && s.fineWeight <= 1)) return "fineWeight must be 0..1";
  if (s.maxTargetPixels < 0) return "maxTargetPixels must be >= 0";
  for (const double v : {s.hiddenNcc, s.visibleNcc, s.flatSigma, s.texturedSigma, s.meanTolerance,
                         s.meanToleranceShare, s.textureTolerance})
    if (!std::isfinite(v)) return "the thresholds must be finite";
  if (!(s.hiddenNcc < s.visibleNcc) || s.hiddenNcc < -1 || s.visibleNcc > 1)
    return "need -1 <= hiddenNcc < visibleNcc <= 1";
  if (!(s.flatSigma >= 0) || !(s.flatSigma < s.texturedSigma)) return "need 0 <= flatSigma < texturedSigma";
  if (!(s.meanTolerance > 0) || !(s.meanToleranceShare >= 0) || !(s.textureTolerance > 0))
    return "meanTolerance and textureTolerance must be positive, meanToleranceShare >= 0";
  return {};
}

bool TargetOcclusion::Impl::geometry(const glm::dmat4& c2w, Box& target) noexcept {
  // World -> OpenCV camera (Y and Z of the renderer's camera negated), then the plane's
  // homography to normalized coordinates, [r1 r3 t], and its inverse.
  const glm::dmat3 cvToWorld{glm::dvec3(c2w[0]), -glm::dvec3(c2w[1]), -glm::dvec3(c2w[2])};
  const glm::dmat3 rot = glm::transpose(cvToWorld);
  const glm::dvec3 t = -(rot * glm::dvec3(c2w[3]));
  const glm::dmat3 hn(rot[0], rot[2], t);
  const double det = glm::determinant(hn);
  if (!(std::abs(det) > 1e-15) || !std::isfinite(det)) return false;
  const glm::dmat3 hi = glm::inverse(hn);
  // The reference pixel mask pixel i's ray meets; false where none (behind the camera, off the
  // lens model, far outside the reference: there the numbers only need to say so).
  const double limit = 16.0 * (refW + refH);
  auto project = [&](std::size_t i, double& uu, double& vv) {
    const double rx = rayX[i], ry = rayY[i];
    if (std::isnan(rx)) return false;
    const glm::dvec3 q = hi * glm::dvec3(rx, ry, 1.0);
    if (!(q.z > 0)) return false;  // the ray meets the plane behind the camera
    const double X = q.x / q.z, Z = q.y / q.z;
    const double w = A[6] * X + A[7] * Z + A[8];
    if (!(w > 0)) return false;
    uu = (A[0] * X + A[1] * Z + A[2]) / w, vv = (A[3] * X + A[4] * Z + A[5]) / w;
    return std::abs(uu) < limit && std::abs(vv) < limit;
  };
  // First the corners of kCell x kCell cells: a cell whose corners' reference box, grown by its
  // own size, misses the reference (and any cell with a corner without a ray) is far from the
  // target; the rest, grown by two cells (more than the work's margins), are worked out pixel by
  // pixel.
  const int cw = (mw + kCell - 1) / kCell, ch = (mh + kCell - 1) / kCell;
  std::fill(cells.begin(), cells.end(), std::uint8_t{0});
  for (int cy = 0; cy < ch; ++cy)
    for (int cx = 0; cx < cw; ++cx) {
      double lo[2] = {1e300, 1e300}, hi2[2] = {-1e300, -1e300};
      bool near = false;
      for (int k = 0; k < 4 && !near; ++k) {
        const int x = std::min(mw - 1, kCell * (cx + (k & 1))), y = std::min(mh - 1, kCell * (cy + (k >> 1)));
        double uu, vv;
        if (!project(at(x, y), uu, vv)) {
          near = true;
          break;
        }
        lo[0] = std::min(lo[0], uu), lo[1] = std::min(lo[1], vv), hi2[0] = std::max(hi2[0], uu), hi2[1] = std::max(hi2[1], vv);
      }
      const double grow = std::max(hi2[0] - lo[0], hi2[1] - lo[1]) + 1;
      near = near || (lo[0] - grow < refW && hi2[0] + grow > -1 && lo[1] - grow < refH && hi2[1] + grow > -1);
      if (!near) continue;
      for (int y = std::max(0, cy - 2); y <= std::min(ch - 1, cy + 2); ++y)
        for (int x = std::max(0, cx - 2); x <= std::min(cw - 1, cx + 2); ++x) cells[static_cast<std::size_t>(y * cw + x)] = 1;
    }
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const std::size_t i = at(x, y);
      u[i] = v[i] = kNaN;
      double uu, vv;
      if (!cells[static_cast<std::size_t>((y / kCell) * cw + x / kCell)] || !project(i, uu, vv)) continue;
      u[i] = static_cast<float>(uu);
      v[i] = static_cast<float>(vv);
    }
  // Coverage from the steps to the neighbours: the edge's distance in reference pixels over the
  // pixel's side is its share on the target. Pixels whose centre is farther off the reference
  // than their steps (an upper bound of the side) are off it.
  target = {mw, mh, 0, 0};
  const float fw = static_cast<float>(refW), fh = static_cast<float>(refH);
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const std::size_t i = at(x, y);
      cover[i] = 0;
      if (std::isnan(u[i])) continue;  // (and every pixel of a cell far from the target)
      std::size_t nx, ny;
      if (!neighbours(x, y, nx, ny)) continue;
      const float ax = std::abs(u[nx] - u[i]) + std::abs(v[nx] - v[i]), ay = std::abs(u[ny] - u[i]) + std::abs(v[ny] - v[i]);
      const float bound = std::max(ax, ay);  // at least the side below
      const float d = std::min(std::min(u[i] + 0.5f, fw - 0.5f - u[i]), std::min(v[i] + 0.5f, fh - 0.5f - v[i]));
      if (!(d > -0.5f * bound)) continue;
      if (d >= 0.5f * bound) {
        cover[i] = 1;  // wholly inside: 0.5 + d / side >= 1
      } else {
        float lx, ly;
        steps(i, nx, ny, lx, ly);
        const float side = std::sqrt(lx * ly);
        if (!(side > 0) || !std::isfinite(side)) continue;
        cover[i] = clamp01(0.5f + d / side);
      }
      if (cover[i] > 0) {
        target.x0 = std::min(target.x0, x), target.y0 = std::min(target.y0, y);
        target.x1 = std::max(target.x1, x + 1), target.y1 = std::max(target.y1, y + 1);
      }
    }
  return !target.empty();
}

void TargetOcclusion::Impl::levelsOver(const Box& b) noexcept {
  // The frame's block is a box of `footprint` reference pixels; a pyrDown level l is a Gaussian
  // of about 0.6 2^l: the level one below log2 of the footprint matches it.
  const float last = static_cast<float>(levels.size() - 1);
  for (int y = b.y0; y < b.y1; ++y)
    for (int x = b.x0; x < b.x1; ++x) {
      const std::size_t i = at(x, y);
      std::size_t nx, ny;
      if (std::isnan(u[i]) || !neighbours(x, y, nx, ny)) {
        lod[i] = 0;
        continue;
      }
      float lx, ly;
      steps(i, nx, ny, lx, ly);
      const float footprint = std::max(std::min(lx, ly), 0.5f * std::max(lx, ly));
      lod[i] = std::isfinite(footprint) ? std::clamp(std::log2(std::max(footprint, 1e-6f)) - 1.0f, 0.0f, last) : last;
    }
}

void TargetOcclusion::Impl::readFrame(const ImageView& frame, const Box& b) noexcept {
  const int sc = s.scale, W = frame.width, H = frame.height, ch = frame.channels;
  const std::ptrdiff_t stride = frame.rowBytes();
  for (int y = b.y0; y < b.y1; ++y) {
    std::fill(rowAcc.begin() + b.x0, rowAcc.begin() + b.x1, 0u);
    const int fy0 = y * sc, fy1 = std::min(H, fy0 + sc);
    for (int fy = fy0; fy < fy1; ++fy) {
      const std::uint8_t* row = frame.pixels + fy * stride;
      for (int x = b.x0; x < b.x1; ++x) {
        const int fx0 = x * sc, fx1 = std::min(W, fx0 + sc);
        std::uint32_t acc = 0;
        if (ch == 1) {
          for (int fx = fx0; fx < fx1; ++fx) acc += static_cast<std::uint32_t>(row[fx]) << 14;
        } else {
          // OpenCV's RGB2GRAY weights in 14 bits (RGBA: the alpha ignored).
          for (int fx = fx0; fx < fx1; ++fx) {
            const std::uint8_t* p = row + fx * ch;
            acc += 4899u * p[0] + 9617u * p[1] + 1868u * p[2];
          }
        }
        rowAcc[static_cast<std::size_t>(x)] += acc;
      }
    }
    for (int x = b.x0; x < b.x1; ++x) {
      const int count = (std::min(W, x * sc + sc) - x * sc) * (fy1 - fy0);
      F[at(x, y)] = static_cast<float>(static_cast<double>(rowAcc[static_cast<std::size_t>(x)]) / (16384.0 * count));
    }
  }
}

void TargetOcclusion::Impl::sampleReferenceOver(const Box& b, std::vector<float>& dst) noexcept {
  for (int y = b.y0; y < b.y1; ++y)
    for (int x = b.x0; x < b.x1; ++x) {
      const std::size_t i = at(x, y);
      dst[i] = std::isnan(u[i]) ? kNaN : sampleReference(u[i], v[i], lod[i]);
    }
}

bool TargetOcclusion::Impl::update(const ImageView& frame, const glm::dmat4& cameraToWorld) noexcept {
  clearOutput();
  if (!frame.valid() || frame.width != camera.width || frame.height != camera.height) return false;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(cameraToWorld[c][r])) return false;
  Box t;
  if (!geometry(cameraToWorld, t)) return true;  // the target is out of view
  const Box w = workBox(t);
  readFrame(frame, w);
  // Over- or under-exposed: with much of the target clipped, the comparison would be of clipped
  // pixels (and a linear model of the rest): nothing is said hidden.
  double inside = 0, clippedPixels = 0, onTarget = 0;
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      const std::size_t i = at(x, y);
      onTarget += cover[i];
      if (cover[i] < kInside) continue;
      inside += 1;
      clippedPixels += clipped(F[i]);
    }
  mask.clippedShare = inside > 0 ? clippedPixels / inside : 0.0;
  mask.targetInView = true;
  mask.targetPixels = onTarget;
  if (mask.clippedShare > kMaxClippedShare) return true;
  levelsOver(w);
  sampleReferenceOver(w, R0);
  searchShift(t, w);
  shiftReference(w);
  matchBlur(w);
  windowSums(w);
  double gain = 1, bias = 0;
  photometricModel(t, gain, bias);
  mask.gain = gain, mask.bias = bias;
  decide(t, gain, bias);
  clean(t, t.grown(2 + s.featherPasses, mw, mh));
  return true;
}

void TargetOcclusion::Impl::configureGrid(int sc) {
  mw = (camera.width + sc - 1) / sc, mh = (camera.height + sc - 1) / sc;
  const std::size_t n = static_cast<std::size_t>(mw) * static_cast<std::size_t>(mh);
  // Each mask pixel's centre (its block's centre in frame pixels, OpenCV's convention) as a
  // ray of the pinhole: the lens model undone.
  std::vector<cv::Point2f> centres, rays;
  centres.reserve(n);
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const double cxp = 0.5 * (x * sc + std::min(camera.width, x * sc + sc)) - 0.5;
      const double cyp = 0.5 * (y * sc + std::min(camera.height, y * sc + sc)) - 0.5;
      centres.emplace_back(static_cast<float>(cxp), static_cast<float>(cyp));
    }
  rayX.resize(n), rayY.resize(n);
  if (camera.hasDistortion()) {
    const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    cv::undistortPoints(centres, rays, k, std::vector<double>(camera.distortion.begin(), camera.distortion.end()),
                        cv::noArray(), cv::noArray(), cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-9));
    for (std::size_t i = 0; i < n; ++i) {
      rayX[i] = std::isfinite(rays[i].x) ? rays[i].x : kNaN;
      rayY[i] = std::isfinite(rays[i].y) ? rays[i].y : kNaN;
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      rayX[i] = static_cast<float>((centres[i].x - camera.cx) / camera.fx);
      rayY[i] = static_cast<float>((centres[i].y - camera.cy) / camera.fy);
    }
  }
  for (auto* buffer : {&u, &v, &lod, &cover, &F, &R0, &R, &Rb, &gx, &gy, &shiftX, &shiftY, &tmp, &h, &h2})
    buffer->assign(n, 0.0f);
  for (std::vector<float>& q : sums) q.assign(n, 0.0f);
  for (std::vector<float>& q : inner) q.assign(n, 0.0f);
  rowAcc.assign(static_cast<std::size_t>(mw), 0u);
  for (auto* buffer : {&fitR, &fitF, &fitSigmaF, &fitSigmaR, &fitResidual}) buffer->reserve(n);
  out.assign(n, 0);
  cells.assign(static_cast<std::size_t>((mw + kCell - 1) / kCell) * static_cast<std::size_t>((mh + kCell - 1) / kCell), 0);
  mask.width = mw, mask.height = mh, mask.scale = mask.computedScale = sc;
  mask.pixels = out.data();
}

double TargetOcclusion::Impl::targetArea(const glm::dmat4& cameraToWorld) noexcept {
  Box t;
  if (!geometry(cameraToWorld, t)) return 0;
  double area = 0;
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) area += cover[at(x, y)];
  return area;
}

void TargetOcclusion::Impl::upsampleFrom(const Impl& coarse) noexcept {
  clearOutput();
  const OcclusionMask& c = coarse.mask;
  mask.targetInView = c.targetInView;
  mask.targetPixels = 4 * c.targetPixels;
  mask.hiddenShare = c.hiddenShare, mask.clippedShare = c.clippedShare;
  mask.gain = c.gain, mask.bias = c.bias;
  mask.blurLength = 2 * c.blurLength, mask.blurAngleRad = c.blurAngleRad;
  mask.shiftX = 2 * c.shiftX, mask.shiftY = 2 * c.shiftY;
  const Box& cw = coarse.written;
  if (cw.empty()) return;
  // Fine pixel x's centre is coarse pixel (x + 0.5) / 2 - 0.5: the fine pixels within half a coarse
  // pixel of the coarse box (outside it the coarse mask is 0).
  const Box e{std::max(0, 2 * cw.x0 - 1), std::max(0, 2 * cw.y0 - 1), std::min(mw, 2 * cw.x1 + 1),
              std::min(mh, 2 * cw.y1 + 1)};
  const int cmw = coarse.mw, cmh = coarse.mh;
  auto value = [&](int x, int y) -> float {
    return x < cw.x0 || x >= cw.x1 || y < cw.y0 || y >= cw.y1 ? 0.0f : coarse.out[coarse.at(x, y)];
  };
  for (int y = e.y0; y < e.y1; ++y) {
    const float cy = std::clamp((static_cast<float>(y) + 0.5f) * 0.5f - 0.5f, 0.0f, static_cast<float>(cmh - 1));
    const int y0 = static_cast<int>(cy);
    const float ay = cy - static_cast<float>(y0);
    for (int x = e.x0; x < e.x1; ++x) {
      const float cx = std::clamp((static_cast<float>(x) + 0.5f) * 0.5f - 0.5f, 0.0f, static_cast<float>(cmw - 1));
      const int x0 = static_cast<int>(cx);
      const float ax = cx - static_cast<float>(x0);
      const float m = (value(x0, y0) * (1 - ax) + value(x0 + 1, y0) * ax) * (1 - ay) +
                      (value(x0, y0 + 1) * (1 - ax) + value(x0 + 1, y0 + 1) * ax) * ay;
      out[at(x, y)] = static_cast<std::uint8_t>(std::min(255.0f, m + 0.5f));
    }
  }
  written = e;
}

TargetOcclusion::TargetOcclusion(std::unique_ptr<Impl> impl, std::unique_ptr<Impl> coarse) noexcept
    : impl_(std::move(impl)), coarse_(std::move(coarse)) {}
TargetOcclusion::~TargetOcclusion() = default;

std::unique_ptr<TargetOcclusion> TargetOcclusion::create(const CameraModel& camera, const ImageView& reference,
                                                         const std::array<double, 9>& planeToImage,
                                                         const OcclusionSettings& settings, Diagnostics& diagnostics) {
  if (const std::string p = camera.problem(); !p.empty()) {
    diagnostics.error("camera", p);
    return nullptr;
  }
  if (const std::string p = settings.problem(); !p.empty()) {
    diagnostics.error("occlusion settings", p);
    return nullptr;
  }
  if (!reference.valid() || reference.channels != 1 || reference.width < 16 || reference.height < 16) {
    diagnostics.error("target", "the reference image must be grey and at least 16x16 pixels");
    return nullptr;
  }
  const cv::Matx33d a(planeToImage.data());
  const double det = cv::determinant(a);
  bool finite = true;
  for (const double x : planeToImage) finite = finite && std::isfinite(x);
  if (!finite || !(std::abs(det) > 1e-300)) {
    diagnostics.error("target", "the reference's plane-to-image mapping is singular or not finite");
    return nullptr;
  }
  try {
    auto impl = std::make_unique<Impl>();
    impl->camera = camera;
    impl->s = settings;
    std::copy(planeToImage.begin(), planeToImage.end(), impl->A);
    impl->refW = reference.width, impl->refH = reference.height;
    const cv::Mat grey(reference.height, reference.width, CV_8UC1, const_cast<std::uint8_t*>(reference.pixels),
                       static_cast<std::size_t>(reference.rowBytes()));
    cv::Mat level;
    grey.convertTo(level, CV_32F);
    impl->levels.push_back(level);
    while (impl->levels.size() < 10 && std::min(impl->levels.back().cols, impl->levels.back().rows) >= 8) {
      cv::Mat down;
      cv::pyrDown(impl->levels.back(), down);
      impl->levels.push_back(down);
    }
    for (std::size_t l = 0; l < impl->levels.size(); ++l) impl->levelScale.push_back(std::ldexp(1.0f, -static_cast<int>(l)));
    impl->configureGrid(settings.scale);
    // Twice the scale for a target that fills much of the view (maxTargetPixels), sharing the
    // reference's pyramid.
    std::unique_ptr<Impl> coarse;
    if (settings.maxTargetPixels > 0 && 2 * settings.scale <= 16) {
      coarse = std::make_unique<Impl>();
      coarse->camera = camera;
      coarse->s = settings;
      coarse->s.scale = 2 * settings.scale;
      std::copy(std::begin(impl->A), std::end(impl->A), coarse->A);
      coarse->refW = impl->refW, coarse->refH = impl->refH;
      coarse->levels = impl->levels;  // (headers: the pixels are shared)
      coarse->levelScale = impl->levelScale;
      coarse->configureGrid(coarse->s.scale);
    }
    return std::unique_ptr<TargetOcclusion>(new TargetOcclusion(std::move(impl), std::move(coarse)));
  } catch (const cv::Exception& e) {
    diagnostics.error("target", std::string("OpenCV failed: ") + e.what());
    return nullptr;
  }
}

std::unique_ptr<TargetOcclusion> TargetOcclusion::create(const CameraModel& camera, const PlanarMap& map,
                                                         const OcclusionSettings& settings, Diagnostics& diagnostics) {
  if (map.keyframes.empty()) {
    diagnostics.error("map", "the map has no reference keyframe");
    return nullptr;
  }
  const PlanarKeyframe& k = map.keyframes[0];
  if (k.grey.size() != static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height)) {
    diagnostics.error("map", "the reference keyframe's image does not match its size");
    return nullptr;
  }
  return create(camera, ImageView{k.grey.data(), k.width, k.height, 1, 0}, k.planeToImage, settings, diagnostics);
}

bool TargetOcclusion::update(const ImageView& frame, const glm::dmat4& cameraToWorld) noexcept {
  // A target that fills much of the view: its mask at twice the scale (from a quarter of the
  // pixels), upsampled. Its area on the coarse grid, times four, estimates the fine one's.
  if (coarse_ && frame.valid() && frame.width == impl_->camera.width && frame.height == impl_->camera.height) {
    bool finite = true;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(cameraToWorld[c][r]);
    if (finite && 4 * coarse_->targetArea(cameraToWorld) > impl_->s.maxTargetPixels) {
      const bool ok = coarse_->update(frame, cameraToWorld);
      impl_->upsampleFrom(*coarse_);
      impl_->mask.computedScale = coarse_->mask.scale;
      return ok;
    }
  }
  const bool ok = impl_->update(frame, cameraToWorld);
  impl_->mask.computedScale = impl_->mask.scale;
  return ok;
}
void TargetOcclusion::clear() noexcept {
  impl_->clearOutput();
  impl_->mask.computedScale = impl_->mask.scale;
}
const OcclusionMask& TargetOcclusion::mask() const noexcept { return impl_->mask; }
const CameraModel& TargetOcclusion::camera() const noexcept { return impl_->camera; }
const OcclusionSettings& TargetOcclusion::settings() const noexcept { return impl_->s; }

}  // namespace marionette::ar
