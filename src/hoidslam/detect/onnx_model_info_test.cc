#include "hoidslam/detect/onnx_model_info.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/detect/tiny_onnx_model.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::detect {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ReadOnnxInput, ReadsTheSharedYoloxNanoInput) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(model, "models/yolox_nano.onnx");
  const OnnxInputInfo input = ReadOnnxInput(model);
  EXPECT_EQ(input.name, "images");
  EXPECT_THAT(input.dims, ElementsAre(1, 3, 416, 416));
}

TEST(ReadOnnxInput, MarksSymbolicDimensionsAndSkipsInitializersListedAsInputs) {
  testing::TempDir dir;
  tiny_onnx::WriteBytes(dir / "m.onnx", tiny_onnx::IdentityModel({-1, 3, -1, 320}, "weight"));
  const OnnxInputInfo input = ReadOnnxInput(dir / "m.onnx");
  EXPECT_EQ(input.name, "images");
  EXPECT_THAT(input.dims, ElementsAre(-1, 3, -1, 320));
}

TEST(ReadOnnxInput, GarbageTruncatedAndMissingFilesAreNamedInTheError) {
  testing::TempDir dir;
  const std::string model = tiny_onnx::IdentityModel({1, 3, 64, 64});
  tiny_onnx::WriteBytes(dir / "cut.onnx", model.substr(0, model.size() / 2));
  tiny_onnx::WriteBytes(dir / "text.onnx", "this is not a model\n");
  tiny_onnx::WriteBytes(dir / "empty.onnx", "");
  for (const char* name : {"cut.onnx", "text.onnx", "empty.onnx", "absent.onnx"}) {
    try {
      ReadOnnxInput(dir / name);
      ADD_FAILURE() << name << ": expected an InputError";
    } catch (const core::InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(name));
    }
  }
}

}  // namespace
}  // namespace hoidslam::detect
