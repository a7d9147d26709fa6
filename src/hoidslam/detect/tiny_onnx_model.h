#pragma once
// Test helper: hand-encodes minimal ONNX models (a few protobuf fields), so tests can feed the ONNX reader and
// the detector models with shapes no real detector has.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hoidslam::detect::tiny_onnx {

// A model with one float input "images" of `input_dims` (-1 = symbolic dimension "dynamic") passed through an
// Identity node to the output "output", and, when `weight_name` is not empty, an initializer of that name also
// listed among the graph inputs (before "images"), as older exporters do.
std::string IdentityModel(const std::vector<std::int64_t>& input_dims, const std::string& weight_name = "");

// Writes `bytes` to `path` (binary); throws std::runtime_error on failure.
void WriteBytes(const std::filesystem::path& path, const std::string& bytes);

}  // namespace hoidslam::detect::tiny_onnx
