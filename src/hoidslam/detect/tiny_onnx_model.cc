#include "hoidslam/detect/tiny_onnx_model.h"

#include <fstream>
#include <stdexcept>

namespace hoidslam::detect::tiny_onnx {
namespace {

std::string Varint(std::uint64_t value) {
  std::string out;
  do {
    auto byte = static_cast<std::uint8_t>(value & 0x7F);
    value >>= 7;
    if (value != 0) byte |= 0x80;
    out.push_back(static_cast<char>(byte));
  } while (value != 0);
  return out;
}

std::string VarintField(std::uint32_t field, std::uint64_t value) { return Varint(field << 3 | 0) + Varint(value); }

std::string BytesField(std::uint32_t field, const std::string& bytes) {
  return Varint(field << 3 | 2) + Varint(bytes.size()) + bytes;
}

// ValueInfoProto{name, type: TypeProto{tensor_type{elem_type FLOAT, shape}}}.
std::string FloatTensorInfo(const std::string& name, const std::vector<std::int64_t>& dims) {
  std::string shape;
  for (const std::int64_t d : dims) {
    shape += BytesField(1, d >= 0 ? VarintField(1, static_cast<std::uint64_t>(d)) : BytesField(2, "dynamic"));
  }
  const std::string tensor_type = VarintField(1, 1) + BytesField(2, shape);
  return BytesField(1, name) + BytesField(2, BytesField(1, tensor_type));
}

}  // namespace

std::string IdentityModel(const std::vector<std::int64_t>& input_dims, const std::string& weight_name) {
  const std::string node = BytesField(1, "images") + BytesField(2, "output") + BytesField(4, "Identity");
  std::string graph = BytesField(1, node) + BytesField(2, "tiny");
  if (!weight_name.empty()) {
    // TensorProto{dims: [1], data_type: FLOAT, float_data: [0], name}
    const std::string tensor =
        VarintField(1, 1) + VarintField(2, 1) + BytesField(4, std::string(4, '\0')) + BytesField(8, weight_name);
    graph += BytesField(5, tensor) + BytesField(11, FloatTensorInfo(weight_name, {1}));
  }
  graph +=
      BytesField(11, FloatTensorInfo("images", input_dims)) + BytesField(12, FloatTensorInfo("output", input_dims));
  const std::string opset = VarintField(2, 11);
  return VarintField(1, 7) + BytesField(7, graph) + BytesField(8, opset);
}

void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace hoidslam::detect::tiny_onnx
