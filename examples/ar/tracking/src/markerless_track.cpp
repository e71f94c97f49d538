#include "markerless_impl.hpp"

// Measuring a pose from a prediction: KLT against the keyframe warped into the view (the blur model
// smearing it as the frame is), RANSAC and the pose, then the evidence the gates judge.

namespace marionette::ar {

namespace {

// Bilinear sample of a grey image; false outside it.
bool sample(const cv::Mat& image, float x, float y, float& out) noexcept {
  if (!(x >= 0) || !(y >= 0) || x > static_cast<float>(image.cols - 2) || y > static_cast<float>(image.rows - 2))
    return false;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const std::uint8_t* r0 = image.ptr<std::uint8_t>(y0);
  const std::uint8_t* r1 = image.ptr<std::uint8_t>(y0 + 1);
  out = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

// Zero-mean normalized cross-correlation of the (2 half + 1)^2 patches around a in `templ` and
// b in `frame`; NaN where a patch leaves its image or is flat.
double patchNcc(const cv::Mat& templ, cv::Point2f a, const cv::Mat& frame, cv::Point2f b, int half) noexcept {
  double st = 0, sf = 0, stt = 0, sff = 0, stf = 0;
  int n = 0;
  for (int dy = -half; dy <= half; ++dy)
    for (int dx = -half; dx <= half; ++dx) {
      float t = 0, f = 0;
      if (!sample(templ, a.x + static_cast<float>(dx), a.y + static_cast<float>(dy), t) ||
          !sample(frame, b.x + static_cast<float>(dx), b.y + static_cast<float>(dy), f))
        return std::numeric_limits<double>::quiet_NaN();
      st += t, sf += f, stt += double(t) * t, sff += double(f) * f, stf += double(t) * f;
      ++n;
    }
  const double vt = stt - st * st / n, vf = sff - sf * sf / n;
  if (!(vt > 1e-6 * n) || !(vf > 1e-6 * n)) return std::numeric_limits<double>::quiet_NaN();
  return (stf - st * sf / n) / std::sqrt(vt * vf);
}

}  // namespace

namespace markerless {

void addKeyframeError(const KeyframeData& kf, double covariance[36]) noexcept {
  // Its position error as it is, its orientation error as it is and through its lever to the
  // floor it saw (an error of 0.3 deg moves floor points 3 m away by 16 mm, and the pose
  // measured from them with them). First order: a rotation error w moves the floor point at
  // lever v by w x v = -[v]x w, so the position block gains [v]x S [v]x^T with S the keyframe's
  // rotation block.
  for (std::size_t i = 0; i < 36; ++i) covariance[i] += kf.covariance[i];
  const glm::dvec3& v = kf.lever;
  const double vx[3][3] = {{0, -v.z, v.y}, {v.z, 0, -v.x}, {-v.y, v.x, 0}};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double sum = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) sum += vx[a][i] * kf.covariance[static_cast<std::size_t>(i * 6 + j)] * vx[b][j];
      covariance[static_cast<std::size_t>((3 + a) * 6 + 3 + b)] += sum;
    }
}

void fill(cv::Mat& image, std::uint8_t value) noexcept {
  for (int y = 0; y < image.rows; ++y) std::memset(image.ptr<std::uint8_t>(y), value, static_cast<std::size_t>(image.cols));
}

double narrowestSpread(const std::vector<cv::Point2f>& points) noexcept {
  if (points.size() < 2) return 0;
  double mx = 0, my = 0;
  for (const cv::Point2f& p : points) mx += p.x, my += p.y;
  const double n = static_cast<double>(points.size());
  mx /= n, my /= n;
  double sxx = 0, syy = 0, sxy = 0;
  for (const cv::Point2f& p : points) {
    sxx += (p.x - mx) * (p.x - mx);
    syy += (p.y - my) * (p.y - my);
    sxy += (p.x - mx) * (p.y - my);
  }
  sxx /= n, syy /= n, sxy /= n;
  return std::sqrt(std::max(0.0, 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy)));
}

}  // namespace markerless

bool MarkerlessTracker::Impl::track(const PlanarPose& prediction, int keyframe, Measurement& out) {
  const StageTimer timer(stats.kltMs);
  stats.predicted = true;
  stats.predictedCameraToWorld = cameraToWorld(prediction);
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  const cv::Mat& frame = grey.pinhole();
  PlanarPose current = prediction;
  out = Measurement{};
  int inliers = 0;
  double rms = 0;
  const cv::Mat* usedTemplate = &warped;
  for (int pass = 0; pass <= settings.refinements; ++pass) {
    const cv::Matx33d G = planeToImageHomography(K, current);
    const cv::Matx33d W0 = G * kf.imageToPlane;  // keyframe level-0 pixel -> frame pixel
    // The pyramid level whose scale is nearest the view's (a 1 px step in the level image
    // moves about 1 px in the frame): warping from it does not alias.
    const double scale = homographyScaleAt(W0, cv::Point2f(static_cast<float>(kf.levels[0].cols) * 0.5f,
                                                           static_cast<float>(kf.levels[0].rows) * 0.5f));
    int level = 0;
    while (level + 1 < static_cast<int>(kf.levels.size()) && scale < 0.7 / (1 << level)) ++level;
    const double f = 1.0 / (1 << level);
    // Level pixel (centre convention) -> level-0 pixel: x0 = (x + 0.5) / f - 0.5.
    const cv::Matx33d levelToBase(1 / f, 0, 0.5 / f - 0.5, 0, 1 / f, 0.5 / f - 0.5, 0, 0, 1);

    predicted.clear();
    planePoints.clear();
    levelPoints.clear();
    const float margin = static_cast<float>(settings.kltWindow);
    // Fewer against the floor: its keyframe is a whole frame, and what its corners add past 100
    // buys less than the time they take (docs/tracking.md, "The floor around the target").
    const int wanted = kf.reference ? settings.trackedCorners : std::min(settings.trackedCorners, settings.floorTrackedCorners);
    for (std::size_t c = 0; c < kf.corners.size() && static_cast<int>(predicted.size()) < wanted; ++c) {
      const cv::Vec3d h = W0 * cv::Vec3d(kf.corners[c].x, kf.corners[c].y, 1.0);
      if (h[2] <= 1e-9) continue;
      const float u = static_cast<float>(h[0] / h[2]), v = static_cast<float>(h[1] / h[2]);
      if (u < margin || v < margin || u >= static_cast<float>(frame.cols) - margin ||
          v >= static_cast<float>(frame.rows) - margin)
        continue;
      predicted.emplace_back(u, v);
      planePoints.push_back(kf.cornerPlane[c]);
      levelPoints.emplace_back(static_cast<float>((kf.corners[c].x + 0.5) * f - 0.5),
                               static_cast<float>((kf.corners[c].y + 0.5) * f - 0.5));
    }
    if (predicted.size() < static_cast<std::size_t>(std::max(settings.minLimitedInliers, 6))) return false;
    // Around the keyframe the template is flat at the frame's mean: no false edge where the
    // keyframe ends for KLT's coarse levels, and no texture KLT could match at zero motion (a
    // copy of the frame there would confirm any prediction).
    const cv::Mat& level0 = kf.levels[static_cast<std::size_t>(level)];
    double gain = 1, bias = 0;
    const bool adjust = matchGain(level0, levelPoints, frame, predicted, settings.kltWindow, gain, bias) &&
                        (std::abs(gain - 1) > 0.03 || std::abs(bias) > 3);
    // Only the region KLT reads is warped (the points' box, grown by the window at the
    // coarsest level): the warp was half of a frame's time over the whole image.
    const auto background = static_cast<std::uint8_t>(std::clamp(kf.meanGrey * gain + bias + 0.5, 0.0, 255.0));
    warped.create(frame.size(), CV_8UC1);
    fill(warped, background);
    float x0 = predicted[0].x, y0 = predicted[0].y, x1 = x0, y1 = y0;
    for (const cv::Point2f& p : predicted) {
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
    const int grow = settings.kltWindow * (1 << (pass == 0 ? settings.pyramidLevels : 1));
    const cv::Rect region = cv::Rect(static_cast<int>(x0) - grow, static_cast<int>(y0) - grow,
                                     static_cast<int>(x1 - x0) + 2 * grow + 1, static_cast<int>(y1 - y0) + 2 * grow + 1) &
                            cv::Rect(0, 0, frame.cols, frame.rows);
    const auto meanGrey = static_cast<std::uint8_t>(std::clamp(kf.meanGrey + 0.5, 0.0, 255.0));
    if (!warpPerspectiveRegion(level0, W0 * levelToBase, warped, region, meanGrey)) return false;
    // The exposure after the warp (the same up to rounding, and only over the region).
    if (adjust) {
      // A table of the 256 grey levels (the same expression per level as per pixel).
      std::array<std::uint8_t, 256> adjusted;
      for (int v = 0; v < 256; ++v)
        adjusted[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(std::clamp(v * gain + bias + 0.5, 0.0, 255.0));
      for (int y = region.y; y < region.y + region.height; ++y) {
        std::uint8_t* row = warped.ptr<std::uint8_t>(y);
        for (int x = region.x; x < region.x + region.width; ++x) row[x] = adjusted[row[x]];
      }
    }
    // Motion blur: the template is smeared as the frame is (motion_blur.hpp). The blur found
    // last frame is used first; without one, the frame's statistics may propose one, which
    // the aligned search then confirms (or not) after KLT.
    MotionBlur proposal;
    if (pass == 0 && !blur.any())
      proposal = estimateMotionBlur(warped, frame, predicted, kMaxBlurFraction * frame.cols, blurScratch);
    PlanarPose estimate;
    for (int attempt = 0; attempt < 2; ++attempt) {
      const cv::Mat* templ = &warped;
      if (blur.any()) {
        blurred.create(frame.size(), CV_8UC1);
        fill(blurred, background);
        applyMotionBlur(warped, blur, region, blurred, blurScratch);
        templ = &blurred;
      }
      found = predicted;
      // A smear longer than the window leaves it little texture along the smear: the window
      // grows with the smear (1.25 times, up to 31 px: docs/tracking.md).
      LucasKanadeOptions lkParams;
      lkParams.window = blur.any() ? std::max(settings.kltWindow, std::min(25, static_cast<int>(blur.lengthPx) | 1))
                                   : settings.kltWindow;
      lkParams.coarseWindow = settings.kltWindow;  // the smear halves with each level
      lkParams.levels = pass == 0 ? settings.pyramidLevels : std::min(settings.pyramidLevels, 1);
      status.resize(predicted.size());
      if (!templatePyramid.buildRegion(*templ, region, background)) return false;
      lk.track(templatePyramid, framePyramid(), predicted, found, status, lkParams);
      usedTemplate = templ;
      stats.blurPx = blur.any() ? blur.lengthPx : 0.0;
      inlierPlane.clear();
      inlierImage.clear();
      inlierFrom.clear();
      for (std::size_t i = 0; i < found.size(); ++i)
        if (status[i]) {
          inlierPlane.push_back(planePoints[i]);
          inlierImage.push_back(found[i]);
          inlierFrom.push_back(predicted[i]);
        }
      if (!robustPlanarPose(K, inlierPlane, inlierImage, 2.0, maxDistance(), solver, mask, estimate, rms, inliers, &homography)) {
        if (attempt == 0 && !blur.any() && proposal.any()) {
          blur = proposal;  // the sharp template found nothing in a smeared frame: try the proposal
          continue;
        }
        return false;
      }
      // Inliers within 2 px of the homography but not of the pose: a degenerate pose (seen with
      // 12 inliers and 10 px after a fast turn), not a measurement. (A target that is no
      // pinhole view at all, as the graffiti pair, needs maxTrackingRmsPx raised.)
      if (rms > std::max(2.0, settings.maxTrackingRmsPx)) return false;
      if (pass > 0 || (!blur.any() && !proposal.any())) break;
      // Misaligned patches look blurred: the search needs a pose TRACKING would accept.
      if (inliers < settings.minTrackingInliers || rms > 2 * settings.maxTrackingRmsPx) break;
      // The blur from patches KLT aligned (the RANSAC inliers): for the next frame, and for
      // this one when it changed clearly (the onset or the end of a smear).
      blurFrom.clear();
      blurTo.clear();
      for (std::size_t i = 0; i < inlierFrom.size(); ++i)
        if (mask[i]) {
          blurFrom.push_back(inlierFrom[i]);
          blurTo.push_back(inlierImage[i]);
        }
      const MotionBlur used = blur;
      blur = refineMotionBlur(warped, frame, blurFrom, blurTo, used.any() ? used : proposal, kMaxBlurFraction * frame.cols,
                              blurScratch);
      proposal = {};
      if (used.any() == blur.any() && std::abs(used.lengthPx - blur.lengthPx) <= 0.2 * std::max(used.lengthPx, 5.0)) break;
    }
    current = estimate;
    if (inliers < settings.minLimitedInliers) return false;
  }
  stats.corners = static_cast<int>(predicted.size());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) stats.planeToImage[static_cast<std::size_t>(r * 3 + c)] = homography(r, c);
  out.pose = current;
  out.rms = rms;
  out.inliers = inliers;
  out.tried = static_cast<int>(predicted.size());
  // The evidence beyond the counts. Spread: the inliers (solver.image) against the corners
  // tried, across the narrowest direction of each.
  const double triedSpread = narrowestSpread(predicted);
  out.spread = triedSpread > 0 ? narrowestSpread(solver.image) / triedSpread : 0;
  // Photometric: the template's patches against the frame's where KLT put them, at up to 48
  // inliers spread over the list (it is interleaved over the keyframe).
  double nccSum = 0;
  int nccCount = 0;
  const std::size_t step = std::max<std::size_t>(1, inlierFrom.size() / 48);
  for (std::size_t i = 0; i < inlierFrom.size() && i < mask.size(); i += step) {
    if (!mask[i]) continue;
    const double c = patchNcc(*usedTemplate, inlierFrom[i], frame, inlierImage[i], 4);
    if (std::isfinite(c)) nccSum += c, ++nccCount;
  }
  out.ncc = nccCount > 0 ? nccSum / nccCount : 0;
  // The covariance from the final step's normal equations (planar_pose.hpp). Where the inliers
  // themselves fit loosely (rms over kLooseFitPx: the template does not match the frame, as under
  // a smear longer than the blur model) and few of the corners tried agree, the ones that agree
  // share one bias: the independent features shrink with the square of that share under 60 %
  // (calibrated on the stress sequences: docs/tracking.md). An occluder leaves the inliers tight
  // and costs nothing here unless it leaves under kFewAgreeShare of them.
  const double share = static_cast<double>(inliers) / std::max(1, out.tried);
  // A tight fit that few agree with (a hand over most of the target) counts for less too, below
  // kFewAgreeShare: the corners left bunch around the hand's edge (a pose from 19 % of them, rms
  // 0.6 px, was 2.0 deg off on a fresh stress seed with 0.6 deg of standard deviation).
  const double looseFit = rms > kLooseFitPx ? std::pow(std::min(1.0, share / 0.6), 2.0)
                                            : std::pow(std::min(1.0, share / kFewAgreeShare), 2.0);
  double covariance[36];
  out.haveCovariance = planarPoseCovariance(K, solver.plane, solver.image, {}, current,
                                            std::max(rms, settings.minFeatureSigmaPx),
                                            settings.effectiveFeatures * looseFit,
                                            covariance);
  if (out.haveCovariance) {
    addKeyframeError(kf, covariance);
    std::copy(covariance, covariance + 36, out.covariance.begin());
    covarianceSigmas(covariance, out.positionSigma, out.rotationSigmaDeg);
  }
  return true;
}

}  // namespace marionette::ar
