// The dense, blur-aware alignment of a planar target (dense_alignment.hpp), on views of the
// standard target rendered here by averaging sharp warps over the exposure while the camera
// turns (not by the aligner's own line model): sharp, a 30 px pan smear, and a 55 px smear of a
// turn about an oblique axis, from a start 2 deg and 2 cm off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "dense_alignment.hpp"
#include "dense_smear_taps.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "planar_pose.hpp"
#include "tracking/scenario_run.hpp"

namespace {

using namespace marionette::ar;

constexpr double kPi = 3.14159265358979323846;
const cv::Matx33d kK(525, 0, 319.5, 0, 525, 239.5, 0, 0, 1);

// World -> OpenCV camera looking from `eye` at `at` (world Y up; the target on Y = 0).
PlanarPose lookAt(const cv::Vec3d& eye, const cv::Vec3d& at) {
  const cv::Vec3d z = cv::normalize(at - eye);
  const cv::Vec3d x = cv::normalize(z.cross(cv::Vec3d(0, 1, 0)));
  const cv::Vec3d y = z.cross(x);
  const cv::Matx33d r(x[0], x[1], x[2], y[0], y[1], y[2], z[0], z[1], z[2]);
  PlanarPose p;
  p.rvec = rodriguesFromRotation(r);
  p.tvec = -(r * eye);
  return p;
}

// The camera turned about its own centre by `angle` radians about `axis` (camera axes).
PlanarPose turned(const PlanarPose& p, const cv::Vec3d& axis, double angle) {
  const cv::Matx33d dr = rotationFromRodrigues(cv::normalize(axis) * angle);
  PlanarPose out;
  out.rvec = rodriguesFromRotation(dr * rotationFromRodrigues(p.rvec));
  out.tvec = dr * p.tvec;
  return out;
}

struct View {
  cv::Mat target;                  // the keyframe, level 0
  std::vector<cv::Mat> levels;
  cv::Matx33d planeToImage;        // plane (X, Z) -> keyframe pixel
  cv::Mat frame;
  ImagePyramid pyramid;
  cv::Matx33d motion = cv::Matx33d::eye();  // last frame's pixel -> this one's
};

// The frame at `mid` while the camera turns by `perFrame` radians a frame interval about `axis`,
// exposed for `exposure` of the interval: 32 sharp renders over the exposure, averaged.
void render(View& v, const PlanarPose& mid, const cv::Vec3d& axis, double perFrame, double exposure) {
  v.target = synthetic::standardTargetGrey(cv::Size(800, 600));
  v.levels.assign(1, v.target);
  for (int l = 1; l < 7; ++l) {
    cv::Mat down;
    cv::pyrDown(v.levels.back(), down);
    v.levels.push_back(down);
  }
  const double metresPerPixel = 0.3 / 800;
  v.planeToImage = cv::Matx33d(1 / metresPerPixel, 0, 399.5, 0, 1 / metresPerPixel, 299.5, 0, 0, 1);
  cv::Mat sum(480, 640, CV_32F, cv::Scalar(0));
  const int n = exposure > 0 ? 32 : 1;
  for (int i = 0; i < n; ++i) {
    const double t = n == 1 ? 0 : ((i + 0.5) / n - 0.5) * exposure;
    const PlanarPose p = turned(mid, axis, perFrame * t);
    const cv::Matx33d g = planeToImage(kK, p) * v.planeToImage.inv();
    cv::Mat sharp;
    // A floor of a darker copy of the target around it (texture, not a flat border).
    cv::warpPerspective(v.target, sharp, g, cv::Size(640, 480), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
    cv::Mat f;
    sharp.convertTo(f, CV_32F);
    sum += f;
  }
  sum /= n;
  cv::Mat noise(480, 640, CV_32F);
  cv::randn(noise, 0, 2.0);
  sum += noise;
  sum.convertTo(v.frame, CV_8U);
  ASSERT_TRUE(v.pyramid.configure(640, 480, 3));
  ASSERT_TRUE(v.pyramid.build(v.frame));
  // A pure turn: K dR K^-1 maps the last frame's pixels to this one's.
  v.motion = kK * rotationFromRodrigues(cv::normalize(axis) * perFrame) * kK.inv();
}

double positionErrorM(const PlanarPose& a, const PlanarPose& b) {
  const cv::Vec3d ca = -(rotationFromRodrigues(a.rvec).t() * a.tvec);
  const cv::Vec3d cb = -(rotationFromRodrigues(b.rvec).t() * b.tvec);
  return cv::norm(ca - cb);
}

double rotationErrorDeg(const PlanarPose& a, const PlanarPose& b) {
  return cv::norm(rodriguesFromRotation(rotationFromRodrigues(a.rvec) * rotationFromRodrigues(b.rvec).t())) * 180 / kPi;
}

struct Case {
  const char* name;
  cv::Vec3d axis;
  double degreesPerFrame, exposure;
};

TEST(DenseAlignment, RecoversThePoseSharpAndUnderASmearFromTwoDegreesOff) {
  const PlanarPose truth = lookAt(cv::Vec3d(0.15, 0.55, 0.5), cv::Vec3d(0.02, 0, -0.03));
  // 6 deg a frame at 525 px of focal length is 55 px of image motion; half of it exposed.
  const Case cases[] = {{"sharp", {0, 1, 0}, 0.0, 0.0},
                        {"pan, 30 px", {0, 1, 0}, 6.5, 0.5},
                        {"oblique turn with roll, 55 px", {0.5, 0.8, 0.35}, 6.0, 1.0}};
  cv::setRNGSeed(7);
  DenseAligner aligner;
  DenseAlignmentOptions params;
  aligner.reserve(params);
  for (const Case& c : cases) {
    View v;
    render(v, truth, c.axis, c.degreesPerFrame * kPi / 180, c.exposure);
    // The start: 2 deg about an axis across the view and 2 cm aside.
    PlanarPose start = turned(truth, {1, -0.6, 0.2}, 2.0 * kPi / 180);
    start.tvec += cv::Vec3d(0.02, 0, 0);
    DenseAlignment result;
    const DenseTarget target{v.levels, v.planeToImage};
    // The turn over the exposure guessed as 0.35 of the frame interval's (the truth: 0.5 and 1),
    // its axis turned 30 deg about the optical axis.
    cv::Vec3d guess = smearTurnFromMotion(kK, v.motion, c.exposure > 0 ? 0.35 : 0.0);
    guess = rotationFromRodrigues(cv::Vec3d(0, 0, 30 * kPi / 180)) * guess;
    ASSERT_TRUE(aligner.align(kK, target, v.pyramid, guess, start, params, result)) << c.name;
    // The smear's taps in AVX2 lanes or one by one: the same alignment, to the bit.
    DenseAlignmentOptions scalar = params;
    scalar.wide = false;
    DenseAlignment again;
    ASSERT_TRUE(aligner.align(kK, target, v.pyramid, guess, start, scalar, again)) << c.name;
    EXPECT_EQ(std::memcmp(&again.pose, &result.pose, sizeof(PlanarPose)), 0) << c.name;
    EXPECT_EQ(std::memcmp(again.covariance.data(), result.covariance.data(), sizeof(double) * 36), 0) << c.name;
    EXPECT_EQ(again.renders, result.renders) << c.name;
    const double position = positionErrorM(result.pose, truth), rotation = rotationErrorDeg(result.pose, truth);
    std::printf("%s: %.2f mm %.3f deg, zncc %.3f sigma %.1f, %d samples, sigma(pos) %.2f mm sigma(rot) %.3f deg\n",
                c.name, position * 1e3, rotation, result.zncc, result.sigma, result.samples, result.positionSigma * 1e3,
                result.rotationSigmaDeg);
    EXPECT_LT(position, 0.005) << c.name;
    EXPECT_LT(rotation, 0.3) << c.name;
    EXPECT_GT(result.zncc, 0.9) << c.name;
    // Nothing hidden: where every textured part agrees, they tell what the whole does (the flat
    // parts they leave out add next to nothing).
    // (The agreeing parts' equations are a subset of the whole's, so theirs can only be larger:
    // the bound that can fail is the upper one.)
    std::printf("  parts %d of %d agree\n", result.agreeingParts, result.parts);
    EXPECT_EQ(result.agreeingParts, result.parts) << c.name << ": nothing hides the target";
    ASSERT_TRUE(result.haveAgreeingCovariance) << c.name;
    double agreeingPosition = 0, agreeingRotation = 0;
    covarianceSigmas(result.agreeingCovariance.data(), agreeingPosition, agreeingRotation);
    EXPECT_LT(agreeingRotation, 1.25 * result.rotationSigmaDeg) << c.name;
    EXPECT_LT(agreeingPosition, 1.25 * result.positionSigma) << c.name;
    // The turn over the exposure, started 30-65 % short and 30 deg off its axis: the blur's own.
    const cv::Vec3d trueTurn = cv::normalize(c.axis) * (c.degreesPerFrame * kPi / 180 * c.exposure);
    if (c.exposure > 0) {
      // Its length within a quarter (the blur's length is the loosest of the twelve: 8-16 % long
      // here), its axis within 18 deg.
      const double found = cv::norm(result.smearTurn), expected = cv::norm(trueTurn);
      std::printf("  turn over the exposure %.2f deg (truth %.2f), axis cosine %.3f\n", found * 180 / kPi,
                  expected * 180 / kPi, std::abs(result.smearTurn.dot(trueTurn)) / (found * expected));
      EXPECT_NEAR(found, expected, 0.25 * expected) << c.name;
      EXPECT_GT(std::abs(result.smearTurn.dot(trueTurn)), 0.95 * found * expected) << c.name;
    } else {
      EXPECT_EQ(cv::norm(result.smearTurn), 0.0) << c.name << ": a sharp start stays sharp";
    }
  }
}

// The smear's taps eight samples at a time (AVX2, where the CPU has it) give the scalar loop's
// bits: lanes of 1 to 40 taps, lines that leave the keyframe at any tap or pass behind the
// camera (the lane stops there, outside), groups of fewer than eight.
TEST(DenseAlignment, WideSmearTapsGiveTheScalarLoopsBits) {
  const cv::Mat keyframe = synthetic::standardTargetGrey(cv::Size(200, 150));
  const GreyLevel level{keyframe.data, keyframe.cols, keyframe.rows, static_cast<std::ptrdiff_t>(keyframe.step)};
  const float umax = static_cast<float>(keyframe.cols - 3), vmax = static_cast<float>(keyframe.rows - 3);
  cv::RNG rng(11);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    SmearTaps a;
    a.count = 1 + trial % SmearTaps::kLanes;
    for (int i = 0; i < a.count; ++i) {
      a.taps[i] = rng.uniform(1, 41);
      a.step[i] = 1.0 / a.taps[i];
      const double w = rng.uniform(0.5, 2.0) * (trial % 50 == 0 ? -1 : 1);  // now and then behind the camera
      a.hx[i] = rng.uniform(-20.0, 220.0) * w, a.hy[i] = rng.uniform(-20.0, 170.0) * w, a.hw[i] = w;
      const double length = rng.uniform(0.0, 3.0);
      a.dhx[i] = rng.uniform(-length, length) * w, a.dhy[i] = rng.uniform(-length, length) * w;
      a.dhw[i] = rng.uniform(-0.02, 0.02) * w;
    }
    SmearTaps b = a;
    walkSmearTaps(level, umax, vmax, a, true);
    walkSmearTaps(level, umax, vmax, b, false);
    for (int i = 0; i < a.count; ++i) {
      ASSERT_EQ(a.inside[i], b.inside[i]) << "trial " << trial << " lane " << i;
      if (!b.inside[i]) {
        ++outside;
        continue;
      }
      ++inside;
      for (const auto member : {&SmearTaps::sum, &SmearTaps::gu, &SmearTaps::gv, &SmearTaps::mu, &SmearTaps::mv})
        ASSERT_EQ(std::memcmp(&(a.*member)[i], &(b.*member)[i], sizeof(float)), 0) << "trial " << trial << " lane " << i;
    }
  }
  EXPECT_GT(inside, 3000);
  EXPECT_GT(outside, 3000);
}

// The re-entry search's probe (markerless_reentry.cpp): from a start 4 deg off under a 30 px
// smear, the best shift at the coarse level brings the start within a level pixel's turn (8 px,
// under a degree) and scores well; a start 25 deg off (the target out of the search) scores
// lower, and under the search's bar (a smear correlates a little wherever it is put).
TEST(DenseAlignment, ProbeBringsANearStartWithinTheAlignmentsReach) {
  const PlanarPose truth = lookAt(cv::Vec3d(0.15, 0.55, 0.5), cv::Vec3d(0.02, 0, -0.03));
  cv::setRNGSeed(5);
  DenseAligner aligner;
  DenseAlignmentOptions params;
  aligner.reserve(params);
  View v;
  render(v, truth, {0, 1, 0}, 6.5 * kPi / 180, 0.5);
  const DenseTarget target{v.levels, v.planeToImage};
  const cv::Vec3d smear = smearTurnFromMotion(kK, v.motion, 0.5);
  const PlanarPose near = turned(truth, {1, -0.6, 0}, 4.0 * kPi / 180);
  PlanarPose shifted;
  double score = 0;
  ASSERT_TRUE(aligner.probe(kK, target, v.pyramid, smear, near, params, shifted, score));
  std::printf("probe from 4 deg off: %.2f deg after the shift, score %.3f\n", rotationErrorDeg(shifted, truth), score);
  EXPECT_LT(rotationErrorDeg(shifted, truth), 1.0);
  EXPECT_GT(score, 0.7);
  const PlanarPose far = turned(truth, {1, -0.6, 0}, 25.0 * kPi / 180);
  PlanarPose farShifted;
  double farScore = -2;
  const bool farFound = aligner.probe(kK, target, v.pyramid, smear, far, params, farShifted, farScore);
  std::printf("probe from 25 deg off: %s, score %.3f\n", farFound ? "a shift" : "none", farScore);
  EXPECT_LT(farScore, score);
  EXPECT_LT(farScore, 0.8) << "the re-entry search's kMinReentryScore must refuse it";
  // A probe needs a search: radius 0 is refused, not a score of the start as it is.
  DenseAlignmentOptions none = params;
  none.searchRadius = 0;
  EXPECT_FALSE(aligner.probe(kK, target, v.pyramid, smear, near, none, shifted, score));
}

// A hand over the target: a textured occluder over ~40 % of its projection. The fit must hold on
// the rest, and the parts the hand leaves must agree on their own while the whole does not
// (what lets the tracker draw such a frame, docs/tracking.md); a frame of another picture must
// leave no such agreement.
TEST(DenseAlignment, AHandOverTheTargetLeavesTheOtherPartsAgreeing) {
  const PlanarPose truth = lookAt(cv::Vec3d(0.05, 0.5, 0.35), cv::Vec3d(0.0, 0, -0.02));
  cv::setRNGSeed(11);
  DenseAligner aligner;
  DenseAlignmentOptions params;
  aligner.reserve(params);
  View v;
  render(v, truth, {0, 1, 0}, 0.0, 0.0);
  // The target's projection, and a "hand" over its left 40 %: skin grey with the coarse texture
  // of its own (not the target's), from the top edge down past the middle.
  const cv::Matx33d g = planeToImage(kK, truth) * v.planeToImage.inv();
  std::vector<cv::Point2f> corners{{0, 0}, {799, 0}, {799, 599}, {0, 599}}, projected;
  cv::perspectiveTransform(corners, projected, cv::Matx33f(g));
  const cv::Rect box = cv::boundingRect(projected) & cv::Rect(0, 0, 640, 480);
  ASSERT_GT(box.area(), 200 * 150);
  const cv::Rect hand(box.x, box.y, box.width * 2 / 5, box.height * 4 / 5);
  cv::Mat skin(hand.size(), CV_8U);
  cv::randu(skin, 90, 200);
  cv::GaussianBlur(skin, skin, cv::Size(0, 0), 3);
  skin.copyTo(v.frame(hand));
  ASSERT_TRUE(v.pyramid.build(v.frame));
  PlanarPose start = turned(truth, {1, -0.6, 0.2}, 1.5 * kPi / 180);
  start.tvec += cv::Vec3d(0.01, 0, 0);
  DenseAlignment result;
  const DenseTarget target{v.levels, v.planeToImage};
  ASSERT_TRUE(aligner.align(kK, target, v.pyramid, {0, 0, 0}, start, params, result));
  const double position = positionErrorM(result.pose, truth), rotation = rotationErrorDeg(result.pose, truth);
  std::printf("hand over 32 %%: %.2f mm %.3f deg (sigma %.2f mm %.3f deg), zncc %.3f, parts %d of %d agree, span %.2f\n",
              position * 1e3, rotation, result.positionSigma * 1e3, result.rotationSigmaDeg, result.zncc,
              result.agreeingParts, result.parts, result.agreeingSpan);
  EXPECT_LT(position, 0.01);
  EXPECT_LT(rotation, 0.6);
  // The whole no longer agrees as the tracker asks of it (else this case tests nothing), the
  // parts do as its by-parts gate asks (markerless_tracker.hpp's defaults).
  const MarkerlessSettings gates;
  EXPECT_LT(result.zncc, gates.minDenseZncc);
  EXPECT_GE(result.agreeingParts, gates.minDenseAgreeingParts);
  EXPECT_GE(result.agreeingParts, gates.minDenseAgreeingShare * result.parts);
  EXPECT_GE(result.agreeingSpan, gates.minDenseAgreeingSpan);
  EXPECT_LT(result.agreeingParts, result.parts) << "the parts under the hand do not agree";
  // What the agreeing parts alone tell: the hand's samples added terms to the normal equations
  // but no information, so the pose the tracker draws by parts is less certain than the whole's
  // fit says (a pose 3.0 deg off on a stress sequence was given sigma 0.51 deg by the whole,
  // 1.50 deg by its agreeing parts: docs/tracking.md).
  ASSERT_TRUE(result.haveAgreeingCovariance);
  double agreeingPosition = 0, agreeingRotation = 0;
  covarianceSigmas(result.agreeingCovariance.data(), agreeingPosition, agreeingRotation);
  std::printf("  from the agreeing parts alone: sigma %.2f mm %.3f deg\n", agreeingPosition * 1e3, agreeingRotation);
  EXPECT_GT(agreeingRotation, 1.1 * result.rotationSigmaDeg);
  EXPECT_GT(agreeingPosition, 1.1 * result.positionSigma);
  EXPECT_LT(rotation, 3 * agreeingRotation) << "the agreeing parts' sigma covers the error";

  // Another picture where the target should be (the view turned upside down): whatever pose the fit ends at, its parts do not agree.
  View other;
  render(other, truth, {0, 1, 0}, 0.0, 0.0);
  cv::flip(other.frame, other.frame, -1);  // the same texture's statistics, turned half round
  ASSERT_TRUE(other.pyramid.build(other.frame));
  // (The fit may also fail outright: that is as good.)
  DenseAlignment wrong;
  const bool aligned = aligner.align(kK, target, other.pyramid, {0, 0, 0}, start, params, wrong);
  std::printf("another picture: %s, zncc %.3f, parts %d of %d agree\n", aligned ? "aligned" : "no fit", wrong.zncc,
              wrong.agreeingParts, wrong.parts);
  if (aligned) {
    EXPECT_LT(wrong.agreeingParts, 2);
    EXPECT_LT(wrong.zncc, 0.5);
  }
}

}  // namespace
