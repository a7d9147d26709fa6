// `hoidslam vocabulary`: trains a bag-of-words vocabulary on the ORB descriptors of a set of images and writes it
// as a vocabulary file (docs/vocabulary.md).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/options.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/features/orb_extractor.h"
#include "hoidslam/io/files.h"

namespace hoidslam::apps {
namespace {

struct VocabularyArgs {
  std::vector<std::string> image_folders;
  std::string out;
  int features = core::OrbOptions{}.n_features;
  bow::VocabularyOptions options;
};

// The images of every folder, folder by folder in the order given, each folder's sorted by file name.
std::vector<std::filesystem::path> TrainingImages(const std::vector<std::string>& folders) {
  std::vector<std::filesystem::path> images;
  for (const std::string& folder : folders) {
    const std::vector<std::filesystem::path> in_folder = io::ImagesIn(folder);
    images.insert(images.end(), in_folder.begin(), in_folder.end());
  }
  if (images.empty()) {
    throw core::InputError::ForParameter("--images", fmt::format("no .png, .jpg or .jpeg image in {}",
                                                                 fmt::join(folders, ", ")));
  }
  return images;
}

void RunVocabulary(const VocabularyArgs& args) {
  args.options.Check();
  if (args.features < 1) {
    throw core::InputError::ForParameter("--features", fmt::format("must be >= 1, got {}", args.features));
  }
  const core::Stopwatch clock;
  const std::vector<std::filesystem::path> images = TrainingImages(args.image_folders);
  // Tracking's extractor and settings (config/*.yaml, ORBextractor.*), so the words are those frames will have.
  core::OrbOptions orb;
  orb.n_features = args.features;
  features::OrbExtractor extractor(orb);
  std::vector<cv::Mat> descriptors_per_image;
  std::vector<cv::KeyPoint> keypoints;
  {
    core::ProgressReporter progress("vocabulary: ORB", images.size());
    for (const std::filesystem::path& image : images) {
      cv::Mat descriptors;
      extractor.Extract(io::ReadImage(image, cv::IMREAD_GRAYSCALE, "training"), keypoints, descriptors);
      descriptors_per_image.push_back(descriptors);
      progress.Update(descriptors_per_image.size());
    }
  }
  const double extraction_seconds = clock.ElapsedSeconds();
  const bow::Vocabulary vocabulary = bow::Vocabulary::Train(descriptors_per_image, args.options);
  vocabulary.Save(args.out);
  fmt::print("{}: {} word{} (k {}, L {}) from {} image{}, {} descriptor{}; ORB {:.1f} s, training {:.1f} s; {:.2f} MB, "
             "identity {}\n",
             args.out, vocabulary.word_count(), vocabulary.word_count() == 1 ? "" : "s", vocabulary.branching(),
             vocabulary.levels(), images.size(), images.size() == 1 ? "" : "s", vocabulary.training_descriptors(),
             vocabulary.training_descriptors() == 1 ? "" : "s", extraction_seconds,
             clock.ElapsedSeconds() - extraction_seconds,
             static_cast<double>(std::filesystem::file_size(args.out)) / 1e6, vocabulary.identity());
}

}  // namespace

void AddVocabularyCommand(CLI::App& app) {
  auto args = std::make_shared<VocabularyArgs>();
  bow::VocabularyOptions& options = args->options;
  CLI::App* command = app.add_subcommand(
      "vocabulary",
      "Train a bag-of-words vocabulary (a k-ary tree of L levels of ORB descriptors, as DBoW2's for ORB-SLAM) on the "
      "images of some folders and write it as a vocabulary file (docs/vocabulary.md)");
  command
      ->add_option("--images", args->image_folders,
                   "Folders of training images: every .png, .jpg and .jpeg directly in each (not in subfolders), "
                   "folder by folder, each sorted by file name")
      ->required()
      ->expected(1, -1);
  command->add_option("--out", args->out, "Vocabulary file to write (complete or not at all), e.g. orb.hbow")
      ->required();
  command->add_option("--features", args->features, "ORB features per image (tracking's ORBextractor.nFeatures)")
      ->capture_default_str();
  command->add_option("--branching", options.branching, "Children of a node, k")->capture_default_str();
  command->add_option("--levels", options.levels, "Levels of the tree, L: at most k^L words")->capture_default_str();
  command->add_option("--iterations", options.max_iterations, "Most k-majority rounds at a node")
      ->capture_default_str();
  command->add_option("--seed", options.seed, "Seed of the k-means++ choice of initial centres")
      ->capture_default_str();
  command
      ->add_option("--threads", options.threads,
                   "Nodes clustered at once (0: one per core); the vocabulary is the same for every count")
      ->capture_default_str();
  command->callback([args] { RunVocabulary(*args); });
}

}  // namespace hoidslam::apps
