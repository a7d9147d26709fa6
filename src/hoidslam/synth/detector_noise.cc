#include "hoidslam/synth/detector_noise.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/office.h"
#include "hoidslam/synth/option_checks.h"
#include "hoidslam/synth/random.h"

namespace hoidslam::synth {
namespace {

core::Detection Labelled(core::Detection detection, const std::string& label) {
  detection.label = label;
  detection.class_id = CocoClassId(label);
  return detection;
}

// Clips a box to the image; an empty result means the box left the image.
cv::Rect2f Clip(const cv::Rect2f& box, int width, int height) {
  return box & cv::Rect2f(0.0F, 0.0F, static_cast<float>(width), static_cast<float>(height));
}

}  // namespace

bool DetectorNoiseOptions::Any() const {
  return miss_rate > 0.0 || box_jitter > 0.0 || false_positive_rate > 0.0 || class_confusion_rate > 0.0;
}

std::string DetectorNoiseOptions::Describe() const {
  if (!Any()) return "synthetic ground truth";
  return fmt::format("synthetic ground truth + noise (miss {}, jitter {}, false positives {}/frame, confusion {})",
                     miss_rate, box_jitter, false_positive_rate, class_confusion_rate);
}

void DetectorNoiseOptions::Check(const std::string& prefix) const {
  CheckInRange(miss_rate, 0.0, 1.0, prefix + ".miss_rate");
  CheckInRange(box_jitter, 0.0, 1.0, prefix + ".box_jitter");
  CheckInRange(false_positive_rate, 0.0, 100.0, prefix + ".false_positive_rate");
  CheckInRange(class_confusion_rate, 0.0, 1.0, prefix + ".class_confusion_rate");
}

const std::vector<std::string>& SyntheticLabels() {
  static const std::vector<std::string> labels = {"person",   "chair",  "cup",   "book", "bottle",
                                                  "keyboard", "laptop", "mouse", "tv"};
  return labels;
}

std::vector<core::Detection> ApplyDetectorNoise(const std::vector<core::Detection>& truth,
                                                const DetectorNoiseOptions& options, std::uint64_t seed, int width,
                                                int height) {
  if (!options.Any()) return truth;
  Random random(seed);
  const std::vector<std::string>& labels = SyntheticLabels();
  const int label_count = static_cast<int>(labels.size());
  std::vector<core::Detection> noisy;
  noisy.reserve(truth.size() + 2);
  for (const core::Detection& detection : truth) {
    // Every draw happens for every box, so one option's value never shifts another option's random stream.
    const bool missed = random.Bernoulli(options.miss_rate);
    const bool confused = random.Bernoulli(options.class_confusion_rate);
    const int other = random.UniformInt(0, label_count - 2);
    const double jitter[4] = {random.Normal(), random.Normal(), random.Normal(), random.Normal()};
    const double score = random.Uniform(0.5, 1.0);
    if (missed) continue;
    core::Detection out = detection;
    if (confused) {
      // Any label but the true one: skip over it.
      const auto self = std::find(labels.begin(), labels.end(), detection.label) - labels.begin();
      out = Labelled(out, labels[static_cast<std::size_t>(other >= self ? other + 1 : other) % labels.size()]);
    }
    const double w = detection.box.width;
    const double h = detection.box.height;
    const double x0 = detection.box.x + options.box_jitter * w * jitter[0];
    const double y0 = detection.box.y + options.box_jitter * h * jitter[1];
    const double x1 = detection.box.x + w + options.box_jitter * w * jitter[2];
    const double y1 = detection.box.y + h + options.box_jitter * h * jitter[3];
    out.box = Clip(cv::Rect2f(cv::Point2f(static_cast<float>(std::min(x0, x1)), static_cast<float>(std::min(y0, y1))),
                              cv::Point2f(static_cast<float>(std::max(x0, x1)), static_cast<float>(std::max(y0, y1)))),
                   width, height);
    out.score = static_cast<float>(score);
    if (out.box.width >= 1.0F && out.box.height >= 1.0F) noisy.push_back(out);
  }
  // The number of false positives: the whole part of the rate, plus one more with the fractional chance.
  const double whole = std::floor(options.false_positive_rate);
  const int extra = static_cast<int>(whole) + (random.Bernoulli(options.false_positive_rate - whole) ? 1 : 0);
  for (int i = 0; i < extra; ++i) {
    const double bw = random.Uniform(20.0, 0.4 * width);
    const double bh = random.Uniform(20.0, 0.5 * height);
    const double x = random.Uniform(0.0, width - bw);
    const double y = random.Uniform(0.0, height - bh);
    core::Detection fake = Labelled({}, labels[static_cast<std::size_t>(random.UniformInt(0, label_count - 1))]);
    fake.box = cv::Rect2f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(bw), static_cast<float>(bh));
    fake.score = static_cast<float>(random.Uniform(0.3, 0.8));
    noisy.push_back(fake);
  }
  return noisy;
}

}  // namespace hoidslam::synth
