#include "sequence_options.h"

#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"

namespace hoidslam::apps {

void AddSequenceOptions(CLI::App& command, SequenceArgs& args) {
  command.add_option("dataset", args.dataset,
                     "Sequence folder in TUM / Bonn layout (rgb.txt, depth.txt, rgb/, depth/)");
  command.add_option("--rgb-folder", args.rgb_folder,
                     "Instead of a dataset folder: a folder of colour images, paired in name order with --depth-folder");
  command.add_option("--depth-folder", args.depth_folder, "Folder of 16-bit depth PNGs, for --rgb-folder");
  command.add_option("--fps", args.fps, "Frame rate of --rgb-folder / --depth-folder images")->capture_default_str();
  command.add_option("--associations", args.associations,
                     "RGB-D associations file (t_rgb rgb/... t_depth depth/...), relative to the dataset folder");
  command.add_option("--depth-factor", args.depth_factor,
                     "Depth PNG units per metre (default: DepthMapFactor of --settings, else 5000)");
}

io::RgbdSequence OpenSequence(const SequenceArgs& args, std::optional<double> settings_depth_factor,
                              double default_depth_factor) {
  const bool folders = !args.rgb_folder.empty() || !args.depth_folder.empty();
  if (args.dataset.empty() == !folders) {
    throw core::InputError::ForParameter("dataset", "give either a dataset folder or --rgb-folder and --depth-folder");
  }
  if (folders && (args.rgb_folder.empty() || args.depth_folder.empty())) {
    throw core::InputError::ForParameter(args.rgb_folder.empty() ? "--rgb-folder" : "--depth-folder",
                                         "is needed too: image folders come in pairs");
  }
  if (folders && !args.associations.empty()) {
    throw core::InputError::ForParameter("--associations", "applies to a dataset folder, not to image folders");
  }
  if (args.depth_factor && settings_depth_factor) {
    throw core::InputError::ForParameter(
        "--depth-factor", "the settings file gives DepthMapFactor already; give the depth factor in one place");
  }
  io::SequenceOptions options;
  options.depth_factor = default_depth_factor;
  if (args.depth_factor) options.depth_factor = *args.depth_factor;
  if (settings_depth_factor) options.depth_factor = *settings_depth_factor;
  options.associations = args.associations;
  // Both readers refuse a sequence without frames, naming the list file or the folders.
  return folders ? io::RgbdSequence::OpenImageFolders(args.rgb_folder, args.depth_folder, args.fps, options)
                 : io::RgbdSequence::OpenTum(args.dataset, options);
}

std::filesystem::path SequenceFolder(const SequenceArgs& args) {
  if (!args.dataset.empty()) return args.dataset;
  return io::NormalFolder(args.rgb_folder).parent_path();
}

}  // namespace hoidslam::apps
