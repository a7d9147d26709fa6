#include "hoidslam/synth/textures.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"
#include "hoidslam/synth/random.h"

namespace hoidslam::synth {
namespace {

constexpr core::EnumNames<TextureRole, kTextureRoleCount> kRoleNames = {{
    {TextureRole::kWall, "wall"},
    {TextureRole::kFloor, "floor"},
    {TextureRole::kCeiling, "ceiling"},
    {TextureRole::kCarpet, "carpet"},
    {TextureRole::kDesk, "desk"},
    {TextureRole::kMonitorScreen, "monitor_screen"},
    {TextureRole::kMonitorBody, "monitor_body"},
    {TextureRole::kKeyboard, "keyboard"},
    {TextureRole::kMouse, "mouse"},
    {TextureRole::kLaptop, "laptop"},
    {TextureRole::kBookCover, "book_cover"},
    {TextureRole::kCup, "cup"},
    {TextureRole::kBottle, "bottle"},
    {TextureRole::kChair, "chair"},
    {TextureRole::kSkin, "skin"},
    {TextureRole::kHair, "hair"},
    {TextureRole::kShirt, "shirt"},
    {TextureRole::kTrousers, "trousers"},
    {TextureRole::kShoe, "shoe"},
    {TextureRole::kPoster, "poster"},
    {TextureRole::kGeneric, "generic"},
}};

bool HasVariants(TextureRole role) {
  switch (role) {
    case TextureRole::kBookCover:
    case TextureRole::kCup:
    case TextureRole::kBottle:
    case TextureRole::kShirt:
    case TextureRole::kTrousers:
    case TextureRole::kPoster:
    case TextureRole::kGeneric:
      return true;
    default:
      return false;
  }
}

// ---- Procedural building blocks. Every pattern tiles seamlessly: textures repeat across large faces. ----

cv::Scalar RandomColor(Random& rng, int lo, int hi) {
  return {static_cast<double>(rng.UniformInt(lo, hi)), static_cast<double>(rng.UniformInt(lo, hi)),
          static_cast<double>(rng.UniformInt(lo, hi))};
}

cv::Scalar Scaled(const cv::Scalar& color, double factor) {
  return {color[0] * factor, color[1] * factor, color[2] * factor};
}

// Smooth periodic value noise in [0, 1]: `cells` random values per side, smoothstep-interpolated.
cv::Mat PeriodicNoise(int size, int cells, Random& rng) {
  std::vector<float> grid(static_cast<std::size_t>(cells * cells));
  for (float& value : grid) value = static_cast<float>(rng.Uniform());
  cv::Mat noise(size, size, CV_32F);
  const float cell_size = static_cast<float>(size) / static_cast<float>(cells);
  for (int y = 0; y < size; ++y) {
    const float gy = static_cast<float>(y) / cell_size;
    const int y0 = static_cast<int>(gy) % cells;
    const int y1 = (y0 + 1) % cells;
    float ty = gy - std::floor(gy);
    ty = ty * ty * (3.0F - 2.0F * ty);
    auto* row = noise.ptr<float>(y);
    for (int x = 0; x < size; ++x) {
      const float gx = static_cast<float>(x) / cell_size;
      const int x0 = static_cast<int>(gx) % cells;
      const int x1 = (x0 + 1) % cells;
      float tx = gx - std::floor(gx);
      tx = tx * tx * (3.0F - 2.0F * tx);
      const auto at = [&](int gx_index, int gy_index) { return grid[static_cast<std::size_t>(gy_index * cells + gx_index)]; };
      const float top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * tx;
      const float bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * tx;
      row[x] = top + (bottom - top) * ty;
    }
  }
  return noise;
}

// Fractal noise in [0, 1]: octaves of PeriodicNoise, each twice as fine and half as strong.
cv::Mat FractalNoise(int size, int base_cells, int octaves, Random& rng) {
  cv::Mat sum = cv::Mat::zeros(size, size, CV_32F);
  float amplitude = 1.0F;
  float total = 0.0F;
  for (int octave = 0, cells = base_cells; octave < octaves && cells <= size; ++octave, cells *= 2) {
    sum += PeriodicNoise(size, cells, rng) * amplitude;
    total += amplitude;
    amplitude *= 0.5F;
  }
  return sum / total;
}

// Blends `low` and `high` by a per-pixel weight in [0, 1].
cv::Mat Blend(const cv::Mat& weight, const cv::Scalar& low, const cv::Scalar& high) {
  cv::Mat image(weight.size(), CV_8UC3);
  for (int y = 0; y < weight.rows; ++y) {
    const auto* w = weight.ptr<float>(y);
    auto* out = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < weight.cols; ++x) {
      for (int c = 0; c < 3; ++c) out[x][c] = cv::saturate_cast<uchar>(low[c] + (high[c] - low[c]) * w[x]);
    }
  }
  return image;
}

// Adds per-pixel grey grain of +-amplitude.
void AddGrain(cv::Mat& image, int amplitude, Random& rng) {
  for (int y = 0; y < image.rows; ++y) {
    auto* row = image.ptr<cv::Vec3b>(y);
    for (int x = 0; x < image.cols; ++x) {
      const int delta = rng.UniformInt(-amplitude, amplitude);
      for (int c = 0; c < 3; ++c) row[x][c] = cv::saturate_cast<uchar>(row[x][c] + delta);
    }
  }
}

// Calls draw(offset) for the 9 copies of a shape that make it wrap around the texture's borders.
void DrawWrapped(const cv::Mat& image, const std::function<void(cv::Point)>& draw) {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) draw({dx * image.cols, dy * image.rows});
  }
}

void AddSpeckles(cv::Mat& image, int count, int max_radius, const cv::Scalar& lo, const cv::Scalar& hi,
                 Random& rng) {
  for (int i = 0; i < count; ++i) {
    const int centre_y = rng.UniformInt(0, image.rows - 1);  // drawn first: see Random in synth/random.h
    const cv::Point centre(rng.UniformInt(0, image.cols - 1), centre_y);
    const int radius = rng.UniformInt(1, max_radius);
    const double t = rng.Uniform();
    const cv::Scalar color = lo + (hi - lo) * t;
    DrawWrapped(image, [&](cv::Point offset) { cv::circle(image, centre + offset, radius, color, cv::FILLED); });
  }
}

// Short dark bars of varying length in rows: reads as lines of text from a distance.
void AddTextLines(cv::Mat& image, const cv::Rect& area, int line_height, const cv::Scalar& color, Random& rng) {
  for (int y = area.y; y + line_height <= area.y + area.height; y += line_height * 2) {
    int x = area.x;
    while (x < area.x + area.width - 4) {
      const int word = std::min(rng.UniformInt(line_height, line_height * 5), area.x + area.width - x);
      cv::rectangle(image, cv::Rect(x, y, word, line_height), color, cv::FILLED);
      x += word + rng.UniformInt(line_height / 2 + 1, line_height * 2);
    }
  }
}

// Random capital letters: glyph strokes give crisp corners.
void AddLetters(cv::Mat& image, cv::Point origin, int count, double scale, const cv::Scalar& color, Random& rng) {
  std::string text;
  for (int i = 0; i < count; ++i) text += static_cast<char>('A' + rng.UniformInt(0, 25));
  cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, color, std::max(1, static_cast<int>(scale * 2)),
              cv::LINE_8);
}

// ---- One generator per role. ----

cv::Mat PaintedWall(int s, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 4, 5, rng), {150, 165, 175}, {215, 225, 230});
  AddSpeckles(image, s / 2, 2, {90, 100, 110}, {240, 240, 245}, rng);
  AddGrain(image, 6, rng);
  return image;
}

cv::Mat Tiles(int s, int tiles, const cv::Scalar& base, const cv::Scalar& grout, Random& rng) {
  cv::Mat image(s, s, CV_8UC3);
  const int tile = s / tiles;
  for (int ty = 0; ty < tiles; ++ty) {
    for (int tx = 0; tx < tiles; ++tx) {
      cv::rectangle(image, cv::Rect(tx * tile, ty * tile, tile, tile), Scaled(base, rng.Uniform(0.75, 1.15)),
                    cv::FILLED);
    }
  }
  cv::Mat mottling = FractalNoise(s, 8, 4, rng);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      const float m = 0.8F + 0.4F * mottling.at<float>(y, x);
      for (int c = 0; c < 3; ++c) image.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(image.at<cv::Vec3b>(y, x)[c] * m);
    }
  }
  const int grout_width = std::max(1, s / 128);
  for (int i = 0; i < tiles; ++i) {
    cv::rectangle(image, cv::Rect(i * tile, 0, grout_width, s), grout, cv::FILLED);
    cv::rectangle(image, cv::Rect(0, i * tile, s, grout_width), grout, cv::FILLED);
  }
  return image;
}

cv::Mat Floor(int s, Random& rng) {
  cv::Mat image = Tiles(s, 4, {120, 135, 150}, {50, 55, 60}, rng);
  AddSpeckles(image, s / 3, 2, {40, 50, 60}, {200, 210, 220}, rng);
  AddGrain(image, 8, rng);
  return image;
}

cv::Mat Ceiling(int s, Random& rng) {
  cv::Mat image = Tiles(s, 2, {215, 220, 222}, {140, 140, 145}, rng);
  AddSpeckles(image, s * 2, 1, {110, 110, 115}, {160, 160, 165}, rng);
  AddGrain(image, 5, rng);
  return image;
}

cv::Mat Carpet(int s, Random& rng) {
  const cv::Scalar base = RandomColor(rng, 60, 120);
  cv::Mat image = Blend(FractalNoise(s, 16, 4, rng), Scaled(base, 0.6), Scaled(base, 1.3));
  AddSpeckles(image, s * 3, 1, {30, 30, 30}, {200, 200, 200}, rng);
  AddGrain(image, 14, rng);
  return image;
}

cv::Mat Wood(int s, Random& rng) {
  const cv::Mat warp = FractalNoise(s, 4, 4, rng);
  const cv::Mat fine = FractalNoise(s, 32, 2, rng);
  const int stripes = 2 * rng.UniformInt(3, 6);  // whole periods per tile keep the pattern seamless
  cv::Mat weight(s, s, CV_32F);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      const double phase = (y + 40.0 * warp.at<float>(y, x)) * stripes * 2.0 * CV_PI / s;
      weight.at<float>(y, x) = static_cast<float>(0.35 * (1.0 + std::sin(phase)) + 0.3 * fine.at<float>(y, x));
    }
  }
  cv::Mat image = Blend(weight, {30, 60, 100}, {110, 160, 205});
  AddSpeckles(image, 6, s / 40 + 2, {20, 40, 70}, {40, 70, 110}, rng);  // knots
  AddGrain(image, 6, rng);
  return image;
}

cv::Mat MonitorScreen(int s, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 2, 3, rng), RandomColor(rng, 60, 140), RandomColor(rng, 120, 220));
  for (int i = 0; i < 4; ++i) {  // desktop icons down the left
    cv::rectangle(image, cv::Rect(s / 32, s / 16 + i * s / 7, s / 14, s / 14), RandomColor(rng, 0, 255), cv::FILLED);
  }
  for (int w = 0; w < 3; ++w) {  // windows with title bars and text
    const int width = rng.UniformInt(s / 3, s / 2);
    const int height = rng.UniformInt(s / 4, s / 2);
    const int window_y = rng.UniformInt(2, s - height - s / 12);
    const cv::Rect window(rng.UniformInt(s / 6, s - width - 2), window_y, width, height);
    cv::rectangle(image, window, {245, 245, 245}, cv::FILLED);
    cv::rectangle(image, cv::Rect(window.x, window.y, window.width, s / 24), RandomColor(rng, 40, 200), cv::FILLED);
    AddTextLines(image, cv::Rect(window.x + 4, window.y + s / 16, window.width - 8, window.height - s / 12),
                 std::max(2, s / 80), {60, 60, 60}, rng);
    cv::rectangle(image, window, {80, 80, 80}, 1);
  }
  cv::rectangle(image, cv::Rect(0, s - s / 16, s, s / 16), {50, 45, 40}, cv::FILLED);  // task bar
  AddLetters(image, {s / 2, s - s / 64}, 5, s / 600.0, {230, 230, 230}, rng);
  return image;
}

cv::Mat Plastic(int s, const cv::Scalar& base, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 8, 4, rng), Scaled(base, 0.7), Scaled(base, 1.4));
  AddSpeckles(image, s / 3, 1, Scaled(base, 0.4), Scaled(base, 2.2), rng);
  AddGrain(image, 8, rng);
  return image;
}

cv::Mat Keyboard(int s, Random& rng) {
  cv::Mat image(s, s, CV_8UC3, cv::Scalar(35, 35, 38));
  const int columns = 16;
  const int rows = 6;
  const int key_w = s / columns;
  const int key_h = s / rows;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const cv::Rect key(c * key_w + key_w / 8, r * key_h + key_h / 8, key_w * 3 / 4, key_h * 3 / 4);
      cv::rectangle(image, key, cv::Scalar(200, 200, 200) * rng.Uniform(0.85, 1.0), cv::FILLED);
      AddLetters(image, {key.x + key.width / 4, key.y + key.height * 2 / 3}, 1, key_w / 45.0, {30, 30, 30}, rng);
    }
  }
  AddGrain(image, 5, rng);
  return image;
}

cv::Mat BrushedMetal(int s, Random& rng) {
  cv::Mat streaks(s, s, CV_32F);
  cv::Mat rows = PeriodicNoise(s, s / 2, rng);  // fine across, stretched along x below
  const cv::Mat large = FractalNoise(s, 4, 3, rng);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) streaks.at<float>(y, x) = 0.6F * rows.at<float>(y, x / 16) + 0.4F * large.at<float>(y, x);
  }
  cv::Mat image = Blend(streaks, {150, 150, 155}, {215, 215, 220});
  AddLetters(image, {s / 3, s / 2}, 4, s / 300.0, {110, 110, 115}, rng);  // a logo
  AddGrain(image, 4, rng);
  return image;
}

cv::Mat BookCover(int s, Random& rng) {
  const cv::Scalar base = RandomColor(rng, 20, 230);
  cv::Mat image = Blend(FractalNoise(s, 4, 3, rng), Scaled(base, 0.85), Scaled(base, 1.1));
  const cv::Scalar ink = RandomColor(rng, 0, 255);
  cv::rectangle(image, cv::Rect(s / 10, s / 8, s * 8 / 10, s / 5), ink, cv::FILLED);
  AddLetters(image, {s / 8, s / 8 + s / 7}, 6, s / 300.0, Scaled(base, 0.3), rng);
  cv::circle(image, {s / 2, s * 3 / 5}, s / 6, RandomColor(rng, 0, 255), cv::FILLED);
  cv::rectangle(image, cv::Rect(s / 4, s * 3 / 5, s / 3, s / 8), RandomColor(rng, 0, 255), cv::FILLED);
  AddTextLines(image, cv::Rect(s / 10, s * 4 / 5, s * 8 / 10, s / 8), std::max(2, s / 64), ink, rng);
  cv::rectangle(image, cv::Rect(0, 0, s, s), Scaled(base, 0.4), std::max(1, s / 40));
  AddGrain(image, 5, rng);
  return image;
}

cv::Mat Stripes(int s, int count, bool vertical, const cv::Scalar& a, const cv::Scalar& b, Random& rng) {
  cv::Mat image(s, s, CV_8UC3, a);
  const int period = s / count;
  for (int i = 0; i < count; ++i) {
    const int width = rng.UniformInt(period / 4, period / 2);
    const cv::Rect stripe = vertical ? cv::Rect(i * period, 0, width, s) : cv::Rect(0, i * period, s, width);
    cv::rectangle(image, stripe, b, cv::FILLED);
  }
  return image;
}

cv::Mat Cup(int s, Random& rng) {
  cv::Mat image = Stripes(s, 4, false, RandomColor(rng, 180, 250), RandomColor(rng, 20, 200), rng);
  AddSpeckles(image, 12, s / 16, RandomColor(rng, 0, 255), RandomColor(rng, 0, 255), rng);
  AddLetters(image, {s / 8, s / 2}, 4, s / 250.0, {30, 30, 30}, rng);
  AddGrain(image, 4, rng);
  return image;
}

cv::Mat Bottle(int s, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 4, 3, rng), RandomColor(rng, 40, 120), RandomColor(rng, 100, 200));
  const cv::Rect label(0, s / 3, s, s / 3);
  cv::rectangle(image, label, RandomColor(rng, 180, 255), cv::FILLED);
  AddLetters(image, {s / 16, s / 2}, 5, s / 260.0, RandomColor(rng, 0, 90), rng);
  AddTextLines(image, cv::Rect(s / 16, s / 2 + s / 16, s * 7 / 8, s / 10), std::max(2, s / 90), {40, 40, 40}, rng);
  AddGrain(image, 5, rng);
  return image;
}

cv::Mat Fabric(int s, const cv::Scalar& base, Random& rng) {
  cv::Mat image(s, s, CV_8UC3);
  const cv::Mat noise = FractalNoise(s, 16, 3, rng);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      const double weave = ((x / 2 + y / 2) % 2 == 0) ? 1.15 : 0.85;
      const double m = weave * (0.75 + 0.5 * noise.at<float>(y, x));
      for (int c = 0; c < 3; ++c) image.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(base[c] * m);
    }
  }
  AddSpeckles(image, s / 4, 1, Scaled(base, 0.4), Scaled(base, 1.8), rng);
  return image;
}

cv::Mat Skin(int s, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 8, 4, rng), {140, 160, 205}, {165, 185, 225});
  AddSpeckles(image, s / 8, 1, {110, 130, 175}, {130, 150, 190}, rng);
  AddGrain(image, 3, rng);
  return image;
}

cv::Mat Hair(int s, Random& rng) {
  cv::Mat image(s, s, CV_8UC3, cv::Scalar(25, 30, 40));
  for (int i = 0; i < s * 2; ++i) {
    const int start_y = rng.UniformInt(0, s - 1);
    const cv::Point start(rng.UniformInt(0, s - 1), start_y);
    const int end_dy = rng.UniformInt(s / 16, s / 6);
    const cv::Point end = start + cv::Point(rng.UniformInt(-s / 16, s / 16), end_dy);
    const cv::Scalar color = cv::Scalar(40, 50, 70) * rng.Uniform(0.5, 1.8);
    DrawWrapped(image, [&](cv::Point offset) { cv::line(image, start + offset, end + offset, color, 1); });
  }
  return image;
}

cv::Mat Shirt(int s, int variant, Random& rng) {
  const cv::Scalar a = RandomColor(rng, 30, 230);
  const cv::Scalar b = RandomColor(rng, 30, 230);
  cv::Mat image;
  switch (variant % 4) {
    case 0:  // stripes
      image = Stripes(s, 8, rng.Bernoulli(0.5), a, b, rng);
      break;
    case 1: {  // checks: two crossing stripe layers averaged
      const cv::Mat across = Stripes(s, 8, true, a, b, rng);
      const cv::Mat down = Stripes(s, 8, false, a, Scaled(b, 0.6), rng);
      cv::addWeighted(across, 0.5, down, 0.5, 0.0, image);
      break;
    }
    case 2:  // dots
      image = cv::Mat(s, s, CV_8UC3, a);
      AddSpeckles(image, s / 6, s / 24 + 1, b, Scaled(b, 0.7), rng);
      break;
    default:  // print: blobs in three colours
      image = Blend(FractalNoise(s, 4, 3, rng), a, b);
      AddSpeckles(image, 24, s / 12, RandomColor(rng, 0, 255), RandomColor(rng, 0, 255), rng);
      AddLetters(image, {s / 6, s / 2}, 3, s / 200.0, RandomColor(rng, 0, 255), rng);
      break;
  }
  AddGrain(image, 6, rng);
  return image;
}

cv::Mat Trousers(int s, int variant, Random& rng) {
  static const std::array<cv::Scalar, 4> kBases = {cv::Scalar(120, 70, 40), cv::Scalar(40, 40, 45),
                                                   cv::Scalar(110, 150, 170), cv::Scalar(90, 90, 95)};
  const cv::Scalar base = kBases[static_cast<std::size_t>(variant) % kBases.size()];
  cv::Mat image(s, s, CV_8UC3);
  const cv::Mat noise = FractalNoise(s, 8, 4, rng);
  const int pitch = variant % 2 == 0 ? 4 : 6;  // twill or cord
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      const double diagonal = ((x + y) % pitch < pitch / 2) ? 1.15 : 0.85;
      const double m = diagonal * (0.7 + 0.6 * noise.at<float>(y, x));
      for (int c = 0; c < 3; ++c) image.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(base[c] * m);
    }
  }
  AddSpeckles(image, s / 3, 1, Scaled(base, 0.5), Scaled(base, 1.7), rng);
  // Seams and pockets.
  cv::line(image, {s / 2, 0}, {s / 2, s}, Scaled(base, 0.5), 2);
  cv::rectangle(image, cv::Rect(s / 8, s / 8, s / 4, s / 5), Scaled(base, 1.4), 2);
  return image;
}

cv::Mat Shoe(int s, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 16, 3, rng), {20, 25, 30}, {60, 70, 80});
  cv::line(image, {0, s * 3 / 4}, {s, s * 3 / 4}, {150, 150, 150}, 2);  // stitching
  cv::rectangle(image, cv::Rect(s / 3, s / 6, s / 3, s / 3), {90, 95, 100}, 2);
  AddGrain(image, 6, rng);
  return image;
}

cv::Mat Poster(int s, Random& rng) {
  cv::Mat image = Blend(FractalNoise(s, 2, 3, rng), RandomColor(rng, 100, 255), RandomColor(rng, 0, 255));
  for (int i = 0; i < 8; ++i) {
    const cv::Scalar color = RandomColor(rng, 0, 255);
    const int centre_y = rng.UniformInt(0, s - 1);
    const cv::Point centre(rng.UniformInt(0, s - 1), centre_y);
    const int r = rng.UniformInt(s / 20, s / 6);
    switch (rng.UniformInt(0, 2)) {
      case 0:
        cv::circle(image, centre, r, color, cv::FILLED);
        break;
      case 1:
        cv::rectangle(image, cv::Rect(centre.x - r, centre.y - r / 2, 2 * r, r), color, cv::FILLED);
        break;
      default: {
        const std::vector<cv::Point> triangle = {centre + cv::Point(0, -r), centre + cv::Point(r, r),
                                                 centre + cv::Point(-r, r)};
        cv::fillConvexPoly(image, triangle, color);
        break;
      }
    }
  }
  AddLetters(image, {s / 12, s / 6}, 7, s / 280.0, {20, 20, 20}, rng);
  AddTextLines(image, cv::Rect(s / 12, s * 3 / 4, s * 5 / 6, s / 6), std::max(2, s / 90), {30, 30, 30}, rng);
  AddGrain(image, 4, rng);
  return image;
}

cv::Mat Generic(int s, Random& rng) {
  const cv::Mat noise = FractalNoise(s, 4, 5, rng);
  const std::array<cv::Scalar, 3> palette = {RandomColor(rng, 20, 240), RandomColor(rng, 20, 240),
                                             RandomColor(rng, 20, 240)};
  cv::Mat image(s, s, CV_8UC3);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      const float n = noise.at<float>(y, x);
      const cv::Scalar& color = palette[n < 0.42F ? 0 : (n < 0.55F ? 1 : 2)];
      for (int c = 0; c < 3; ++c) image.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(color[c]);
    }
  }
  AddSpeckles(image, s / 3, 2, {20, 20, 20}, {235, 235, 235}, rng);
  AddGrain(image, 6, rng);
  return image;
}

cv::Mat Procedural(TextureRole role, int variant, int s, Random& rng) {
  switch (role) {
    case TextureRole::kWall: return PaintedWall(s, rng);
    case TextureRole::kFloor: return Floor(s, rng);
    case TextureRole::kCeiling: return Ceiling(s, rng);
    case TextureRole::kCarpet: return Carpet(s, rng);
    case TextureRole::kDesk: return Wood(s, rng);
    case TextureRole::kMonitorScreen: return MonitorScreen(s, rng);
    case TextureRole::kMonitorBody: return Plastic(s, {45, 42, 40}, rng);
    case TextureRole::kKeyboard: return Keyboard(s, rng);
    case TextureRole::kMouse: return Plastic(s, {90, 90, 95}, rng);
    case TextureRole::kLaptop: return BrushedMetal(s, rng);
    case TextureRole::kBookCover: return BookCover(s, rng);
    case TextureRole::kCup: return Cup(s, rng);
    case TextureRole::kBottle: return Bottle(s, rng);
    case TextureRole::kChair: return Fabric(s, {70, 45, 35}, rng);
    case TextureRole::kSkin: return Skin(s, rng);
    case TextureRole::kHair: return Hair(s, rng);
    case TextureRole::kShirt: return Shirt(s, variant, rng);
    case TextureRole::kTrousers: return Trousers(s, variant, rng);
    case TextureRole::kShoe: return Shoe(s, rng);
    case TextureRole::kPoster: return Poster(s, rng);
    case TextureRole::kGeneric: return Generic(s, rng);
  }
  throw core::Error("unknown texture role");
}

// ---- Photos ----

std::vector<std::filesystem::path> ListPhotos(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> photos = io::ImagesIn(folder);
  if (photos.empty()) throw core::InputError::InFile(folder, "texture folder holds no .jpg, .jpeg or .png image");
  return photos;
}

// The largest centred square of the photo, resized to the texture size.
cv::Mat LoadPhoto(const std::filesystem::path& path, int size) {
  const cv::Mat photo = io::ReadImage(path, cv::IMREAD_COLOR, "texture");
  const int side = std::min(photo.cols, photo.rows);
  const cv::Mat square = photo(cv::Rect((photo.cols - side) / 2, (photo.rows - side) / 2, side, side));
  cv::Mat texture;
  cv::resize(square, texture, {size, size}, 0.0, 0.0, side >= size ? cv::INTER_AREA : cv::INTER_LINEAR);
  return texture;
}

std::vector<cv::Mat> MipmapChain(const cv::Mat& image) {
  std::vector<cv::Mat> levels = {image};
  while (levels.back().cols > 4) {
    cv::Mat half;
    cv::resize(levels.back(), half, {levels.back().cols / 2, levels.back().rows / 2}, 0.0, 0.0, cv::INTER_AREA);
    levels.push_back(half);
  }
  return levels;
}

}  // namespace

std::string_view ToString(TextureRole role) { return core::EnumName(kRoleNames, role); }

TextureRole ParseTextureRole(std::string_view name, const std::string& parameter) {
  return core::ParseEnumName(kRoleNames, name, parameter, "texture");
}

void TextureOptions::Check() const {
  if (size < 16 || size > 2048 || (size & (size - 1)) != 0) {
    throw core::InputError::ForParameter("textures.size", fmt::format("must be a power of two in [16, 2048], got {}", size));
  }
  if (variants < 1) throw core::InputError::ForParameter("textures.variants", fmt::format("must be >= 1, got {}", variants));
}

TextureSet::TextureSet(const TextureOptions& options) : texture_size_(options.size) {
  options.Check();
  std::vector<cv::Mat> photos;
  if (!options.photo_folder.empty()) {
    for (const auto& path : ListPhotos(options.photo_folder)) photos.push_back(LoadPhoto(path, options.size));
  }
  for (int r = 0; r < kTextureRoleCount; ++r) {
    const auto role = static_cast<TextureRole>(r);
    const bool photo_posters = role == TextureRole::kPoster && !photos.empty();
    first_[static_cast<std::size_t>(r)] = size();
    count_[static_cast<std::size_t>(r)] =
        photo_posters ? static_cast<int>(photos.size()) : (HasVariants(role) ? options.variants : 1);
    for (int variant = 0; variant < count_[static_cast<std::size_t>(r)]; ++variant) {
      cv::Mat image;
      if (photo_posters) {
        image = photos[static_cast<std::size_t>(variant)];
      } else if (role == TextureRole::kWall && !photos.empty()) {
        image = photos[0];
      } else if (role == TextureRole::kDesk && !photos.empty()) {
        image = photos[1 % photos.size()];
      } else {
        // Each texture has its own stream, so adding a role or variant never changes the others.
        Random rng(FrameSeed(options.seed, static_cast<std::uint64_t>(r), static_cast<std::uint64_t>(variant)));
        image = Procedural(role, variant, options.size, rng);
      }
      levels_.push_back(MipmapChain(image));
    }
  }
}

int TextureSet::Index(TextureRole role, int variant) const {
  const auto r = static_cast<std::size_t>(role);
  const int count = count_.at(r);
  return first_[r] + ((variant % count) + count) % count;
}

int TextureSet::VariantCount(TextureRole role) const { return count_.at(static_cast<std::size_t>(role)); }

}  // namespace hoidslam::synth
