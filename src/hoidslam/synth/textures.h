#pragma once
// Surface textures for the synthetic renderer: a fixed set of square BGR images, each with stable named roles
// (wall, floor, desk, shirt 1..n, ...) so that scenes can pick them by name.
//
// Textures are procedural by default, generated deterministically from a seed with rich, high-contrast
// patterns so that ORB finds features on every surface. Given a folder of photos, the large flat surfaces use
// the photos instead: the wall uses the first photo (sorted by file name), the desk the second, and there is
// one poster per photo (poster i uses photo i); everything else stays procedural.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace hoidslam::synth {

// What a texture is for. Roles marked (n) have TextureOptions::variants variants (posters: one per photo when
// photos are given); the others have one.
enum class TextureRole {
  kWall,           // painted wall with blotches and grain
  kFloor,          // tiles with grout lines and grain
  kCeiling,        // ceiling panels with speckle
  kCarpet,         // speckled carpet
  kDesk,           // wood grain
  kMonitorScreen,  // desktop with windows, icons and text-like lines
  kMonitorBody,    // dark plastic with fine grain
  kKeyboard,       // grid of keys with marks
  kMouse,          // plastic with grain
  kLaptop,         // brushed metal
  kBookCover,      // (n) coloured cover with title blocks and marks
  kCup,            // (n) printed ceramic
  kBottle,         // (n) label with text bands
  kChair,          // woven fabric
  kSkin,           // skin with mild mottling (tint it for skin tones)
  kHair,           // hair strands
  kShirt,          // (n) stripes, checks, prints
  kTrousers,       // (n) twill, denim, cord
  kShoe,           // leather
  kPoster,         // (n) shapes and text-like marks (or a photo)
  kGeneric,        // (n) coloured noise blobs for everything else (cabinets, boxes, plants)
};
inline constexpr int kTextureRoleCount = static_cast<int>(TextureRole::kGeneric) + 1;

std::string_view ToString(TextureRole role);  // "wall", "floor", ..., "monitor_screen", "book_cover", ...
// Parses the names ToString gives; throws InputError naming `parameter` otherwise.
TextureRole ParseTextureRole(std::string_view name, const std::string& parameter);

struct TextureOptions {
  int size = 256;                     // texture side, pixels: a power of two in [16, 2048]
  std::uint64_t seed = 1;             // seed of the procedural patterns
  int variants = 4;                   // variants of each (n) role, >= 1
  std::filesystem::path photo_folder; // optional: every .jpg/.jpeg/.png in it, sorted (see the file comment)

  // Throws InputError naming the parameter ("textures.size", "textures.variants").
  void Check() const;
};

class TextureSet {
 public:
  // Builds the set. Throws InputError naming the folder when photo_folder is missing or holds no image, and
  // naming the file when a photo cannot be read.
  explicit TextureSet(const TextureOptions& options = {});

  int size() const { return static_cast<int>(levels_.size()); }  // number of textures
  int texture_size() const { return texture_size_; }              // side of every level-0 texture, pixels

  // Index of the texture for `role`; `variant` wraps around the role's variant count (any int is valid).
  int Index(TextureRole role, int variant = 0) const;
  int VariantCount(TextureRole role) const;

  // Texture `index` (CV_8UC3, BGR, square, texture_size() pixels).
  const cv::Mat& Image(int index) const { return levels_.at(static_cast<std::size_t>(index)).front(); }
  // Its mipmap chain: level 0 is Image(index), each next level half the side, down to 4 pixels.
  const std::vector<cv::Mat>& Levels(int index) const { return levels_.at(static_cast<std::size_t>(index)); }

 private:
  int texture_size_ = 0;
  std::array<int, kTextureRoleCount> first_{};   // index of each role's first variant
  std::array<int, kTextureRoleCount> count_{};   // number of variants of each role
  std::vector<std::vector<cv::Mat>> levels_;     // per texture, its mipmap chain
};

}  // namespace hoidslam::synth
