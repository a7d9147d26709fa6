#pragma once
// Reads the declared input of an ONNX model without a protobuf library: just enough of the wire format to walk
// ModelProto.graph.input, so a detector can take its input size from the model file instead of asking the user.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hoidslam::detect {

// A graph input as declared in the model.
struct OnnxInputInfo {
  std::string name;
  std::vector<std::int64_t> dims;  // e.g. {1, 3, 416, 416}; -1 for a symbolic or unset dimension
};

// The first input of the model's graph that is not an initializer (older exporters list weights as inputs too).
// Throws InputError naming `path` when the file cannot be read, is not a well-formed protobuf message, or has
// no graph input.
OnnxInputInfo ReadOnnxInput(const std::filesystem::path& path);

}  // namespace hoidslam::detect
