#include "hoidslam/io/trajectory_file.h"

#include <string>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

// A namespace of this file's own: its helpers may share names with another test's of the module, which a
// unity build (scripts/sanitize.sh) compiles into the same translation unit.
namespace hoidslam::io::trajectory_file_test {
namespace {

using ::hoidslam::testing::WriteText;


std::string ErrorOf(const std::filesystem::path& path) {
  try {
    ReadTumTrajectory(path);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ReadTumTrajectory, ToleratesCommentsBlanksCommasAndSortsByTime) {
  testing::TempDir dir;
  WriteText(dir / "t.txt",
            "# ground truth\n"
            "\n"
            "2.0 1 2 3 0 0 0 1\n"
            "1.0,0,0,0,0,0,0,1\r\n"
            "  1.5\t0.5 0 0 0 0 0.7071068 0.7071068  \n");
  const core::Trajectory t = ReadTumTrajectory(dir / "t.txt");
  ASSERT_EQ(t.size(), 3U);
  EXPECT_DOUBLE_EQ(t[0].timestamp, 1.0);
  EXPECT_DOUBLE_EQ(t[1].timestamp, 1.5);
  EXPECT_DOUBLE_EQ(t[2].timestamp, 2.0);
  EXPECT_TRUE(t[2].T_wc.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  // 90 degrees about z.
  EXPECT_NEAR((t[1].T_wc.rotation() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-6);
}

TEST(ReadTumTrajectory, RepeatedTimestampKeepsLastPose) {
  testing::TempDir dir;
  WriteText(dir / "t.txt", "1.0 0 0 0 0 0 0 1\n1.0 5 0 0 0 0 0 1\n");
  const core::Trajectory t = ReadTumTrajectory(dir / "t.txt");
  ASSERT_EQ(t.size(), 1U);
  EXPECT_DOUBLE_EQ(t[0].T_wc.translation().x(), 5.0);
}

TEST(ReadTumTrajectory, BadLinesAreNamedWithFileAndLine) {
  testing::TempDir dir;
  WriteText(dir / "short.txt", "# c\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  EXPECT_EQ(ErrorOf(dir / "short.txt"),
            (dir / "short.txt").string() + ":3: expected 8 values 'timestamp tx ty tz qx qy qz qw', found 7");
  WriteText(dir / "word.txt", "1.0 0 0 zero 0 0 0 1\n");
  EXPECT_EQ(ErrorOf(dir / "word.txt"), (dir / "word.txt").string() + ":1: 'zero' is not a number");
  WriteText(dir / "quat.txt", "1.0 0 0 0 0 0 0 0\n");
  EXPECT_EQ(ErrorOf(dir / "quat.txt"), (dir / "quat.txt").string() + ":1: quaternion is zero");
  EXPECT_EQ(ErrorOf(dir / "absent.txt"), (dir / "absent.txt").string() + ": no such file");
}

TEST(WriteTumTrajectory, RoundTripsToMicrosecondsAndNanometres) {
  testing::TempDir dir;
  core::Trajectory written;
  for (int i = 0; i < 5; ++i) {
    core::StampedPose pose;
    pose.timestamp = 1341846313.592026 + 0.033 * i;
    pose.T_wc = core::PoseFromTranslationQuaternion({0.1 * i, -0.2, 1.5 + i},
                                                    Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized())));
    written.push_back(pose);
  }
  WriteTumTrajectory(dir / "t.txt", written);
  const core::Trajectory read = ReadTumTrajectory(dir / "t.txt");
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_NEAR(read[i].timestamp, written[i].timestamp, 1e-6);
    EXPECT_NEAR((read[i].T_wc.matrix() - written[i].T_wc.matrix()).norm(), 0.0, 1e-8);
  }
}

TEST(ReadTumTrajectory, ReadsRealTumGroundTruthWithItsRepeatedTimestamp) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, "data/tum/groundtruth/fr3_walking_static.txt");
  const core::Trajectory t = ReadTumTrajectory(path);
  ASSERT_GT(t.size(), 1000U);
  for (std::size_t i = 1; i < t.size(); ++i) ASSERT_LT(t[i - 1].timestamp, t[i].timestamp);
}

}  // namespace
}  // namespace hoidslam::io::trajectory_file_test
