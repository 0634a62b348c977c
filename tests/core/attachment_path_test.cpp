// The one attachment validation (clothlab/core/attachment_path.hpp) the CLI and the conformance
// runner share: indices in range, finite targets, no jump between the times read, substep
// times included.
#include <gtest/gtest.h>

#include <clothlab/core/attachment_path.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
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

// A 2 x 2 cloth of 1 m springs (the diagonals longer): its corner 3 at (1, -1, 0) may have its
// target at t = 0 up to a tenth of 1 m away; 0.7 m away, the host would start the cloth
// stretched 70 %, and it is refused naming the attachment and both distances.
TEST(AttachmentPath, ATargetFarFromItsParticleAtTheStartIsRefused) {
  Scene scene;
  scene.rows = scene.cols = 2;
  scene.width = scene.height = 1.0;
  scene.total_mass = 1.0;
  scene.structural = {10.0, 0.0};
  scene.shear = {10.0, 0.0};
  const std::shared_ptr<const ClothModel> model = build_grid_model(scene);
  const std::vector<double>& start = model->rest_positions;
  EXPECT_NO_THROW(
      check_attachment_start(corner, std::vector<double>{1.05, -1.0, 0.0}, start, *model));
  try {
    check_attachment_start(corner, std::vector<double>{1.7, -1.0, 0.0}, start, *model);
    ADD_FAILURE() << "a target 0.7 m from its particle passed";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "attachment 0 (particle 3): target at t = 0 s lies 0.7 m from the particle's "
                 "start, allowed at most 0.1 m (0.1 of its shortest spring's rest length, 1 m): "
                 "start the cloth where its attachments hold it");
  }
}

}  // namespace
}  // namespace clothlab
