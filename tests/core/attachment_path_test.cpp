// The one attachment validation (clothlab/core/attachment_path.hpp) the CLI and the conformance
// runner share: indices in range, finite targets, no jump between the times read, substep
// times included.
#include <gtest/gtest.h>

#include <clothlab/core/attachment_path.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace clothlab {
namespace {

const uint32_t corner[] = {3};

// A 5 m/s path along x held between 1 kHz keys: continuous at 1 ms step starts, a 5 mm jump
// at each key.
void staircase(double t, std::vector<double>& x, std::vector<double>& v) {
  x = {5.0 * std::floor(t * 1000 + 1e-6) / 1000, 0, 0};
  v = {5.0, 0, 0};
}

std::string refusal(const AttachmentTargetReader& read, uint32_t samples_per_step) {
  try {
    check_attachment_path(corner, read, 1e-3, 100, samples_per_step);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(AttachmentPath, AParticlePastTheClothIsRefused) {
  EXPECT_NO_THROW(check_attached_particles(corner, 4));
  EXPECT_THROW(check_attached_particles(corner, 3), std::invalid_argument);
}

TEST(AttachmentPath, AJumpInsideAStepIsCaughtOnlyAtSubstepTimes) {
  EXPECT_EQ(refusal(staircase, 1), "");
  const std::string reason = refusal(staircase, 8);
  EXPECT_NE(reason.find("attachment 0 (particle 3): target jumps"), std::string::npos) << reason;
  EXPECT_NE(reason.find("twice the substep"), std::string::npos) << reason;
}

TEST(AttachmentPath, ASmoothFastPathPassesAtSubstepTimes) {
  const auto circle = [](double t, std::vector<double>& x, std::vector<double>& v) {
    x = {std::cos(50 * t), std::sin(50 * t), 0};
    v = {-50 * std::sin(50 * t), 50 * std::cos(50 * t), 0};
  };
  EXPECT_EQ(refusal(circle, 8), "");
}

TEST(AttachmentPath, ANonFiniteTargetNamesTheTimeAndTheValue) {
  const auto lost = [](double t, std::vector<double>& x, std::vector<double>& v) {
    x = {0, t > 0.0495 ? std::numeric_limits<double>::quiet_NaN() : 0.0, 0};
    v = {0, 0, 0};
  };
  const std::string reason = refusal(lost, 1);
  EXPECT_EQ(reason.rfind("attachment 0 (particle 3): target at t = 0.05", 0), 0u) << reason;
  EXPECT_TRUE(reason.ends_with(" s: position.y = nan, allowed finite")) << reason;
}

}  // namespace
}  // namespace clothlab
