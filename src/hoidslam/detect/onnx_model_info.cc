#include "hoidslam/detect/onnx_model_info.h"

#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string_view>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::detect {
namespace {

// ONNX field numbers (onnx.proto).
constexpr std::uint32_t kModelGraph = 7;
constexpr std::uint32_t kGraphInitializer = 5;
constexpr std::uint32_t kGraphInput = 11;
constexpr std::uint32_t kTensorName = 8;
constexpr std::uint32_t kValueInfoName = 1;
constexpr std::uint32_t kValueInfoType = 2;
constexpr std::uint32_t kTypeTensorType = 1;
constexpr std::uint32_t kTensorTypeShape = 2;
constexpr std::uint32_t kShapeDim = 1;
constexpr std::uint32_t kDimValue = 1;

// Thrown inside this file only; ReadOnnxInput turns it into an InputError naming the file.
struct MalformedMessage {
  std::string what;
};

enum class WireType : std::uint32_t { kVarint = 0, kFixed64 = 1, kBytes = 2, kFixed32 = 5 };

struct Field {
  std::uint32_t number = 0;
  WireType type = WireType::kVarint;
  std::uint64_t varint = 0;  // kVarint
  std::string_view bytes;    // kBytes
};

// Iterates over the fields of one protobuf message.
class MessageReader {
 public:
  explicit MessageReader(std::string_view data) : data_(data) {}

  std::optional<Field> Next() {
    if (position_ == data_.size()) return std::nullopt;
    const std::uint64_t key = ReadVarint();
    Field field;
    field.number = static_cast<std::uint32_t>(key >> 3);
    if (field.number == 0) throw MalformedMessage{"field number 0"};
    switch (key & 7) {
      case 0:
        field.type = WireType::kVarint;
        field.varint = ReadVarint();
        break;
      case 1:
        field.type = WireType::kFixed64;
        Skip(8);
        break;
      case 2: {
        field.type = WireType::kBytes;
        const std::uint64_t length = ReadVarint();
        if (length > data_.size() - position_) throw MalformedMessage{"a field runs past the end of its message"};
        field.bytes = data_.substr(position_, length);
        position_ += length;
        break;
      }
      case 5:
        field.type = WireType::kFixed32;
        Skip(4);
        break;
      default:
        throw MalformedMessage{fmt::format("unsupported wire type {}", key & 7)};
    }
    return field;
  }

 private:
  std::uint64_t ReadVarint() {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (position_ == data_.size()) throw MalformedMessage{"truncated varint"};
      const auto byte = static_cast<std::uint8_t>(data_[position_++]);
      value |= static_cast<std::uint64_t>(byte & 0x7F) << shift;
      if ((byte & 0x80) == 0) return value;
    }
    throw MalformedMessage{"varint longer than 10 bytes"};
  }

  void Skip(std::size_t count) {
    if (count > data_.size() - position_) throw MalformedMessage{"truncated fixed-size field"};
    position_ += count;
  }

  std::string_view data_;
  std::size_t position_ = 0;
};

// The payload of the last length-delimited field `number` of `message`, if any.
std::optional<std::string_view> FindBytes(std::string_view message, std::uint32_t number) {
  std::optional<std::string_view> found;
  MessageReader reader(message);
  while (const std::optional<Field> field = reader.Next()) {
    if (field->number == number && field->type == WireType::kBytes) found = field->bytes;
  }
  return found;
}

std::vector<std::int64_t> ReadDims(std::string_view value_info) {
  std::vector<std::int64_t> dims;
  const auto type = FindBytes(value_info, kValueInfoType);
  if (!type) return dims;
  const auto tensor_type = FindBytes(*type, kTypeTensorType);
  if (!tensor_type) return dims;
  const auto shape = FindBytes(*tensor_type, kTensorTypeShape);
  if (!shape) return dims;
  MessageReader reader(*shape);
  while (const std::optional<Field> dim = reader.Next()) {
    if (dim->number != kShapeDim || dim->type != WireType::kBytes) continue;
    std::int64_t value = -1;  // a symbolic dimension (dim_param) or none at all
    MessageReader dim_reader(dim->bytes);
    while (const std::optional<Field> field = dim_reader.Next()) {
      if (field->number == kDimValue && field->type == WireType::kVarint) {
        value = static_cast<std::int64_t>(field->varint);
      }
    }
    dims.push_back(value);
  }
  return dims;
}

OnnxInputInfo FindInput(std::string_view model) {
  const auto graph = FindBytes(model, kModelGraph);
  if (!graph) throw MalformedMessage{"no graph"};

  std::set<std::string, std::less<>> initializers;
  std::vector<std::string_view> inputs;
  MessageReader reader(*graph);
  while (const std::optional<Field> field = reader.Next()) {
    if (field->type != WireType::kBytes) continue;
    if (field->number == kGraphInitializer) {
      if (const auto name = FindBytes(field->bytes, kTensorName)) initializers.emplace(*name);
    } else if (field->number == kGraphInput) {
      inputs.push_back(field->bytes);
    }
  }
  for (const std::string_view input : inputs) {
    const std::string name(FindBytes(input, kValueInfoName).value_or(""));
    if (initializers.contains(name)) continue;
    return {name, ReadDims(input)};
  }
  throw MalformedMessage{"the graph declares no input"};
}

}  // namespace

OnnxInputInfo ReadOnnxInput(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::InFile(path, "cannot open the model file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw core::InputError::InFile(path, "read error");
  try {
    return FindInput(data);
  } catch (const MalformedMessage& e) {
    throw core::InputError::InFile(path, fmt::format("not an ONNX model ({})", e.what));
  }
}

}  // namespace hoidslam::detect
