// Settings files: the bytes are a settings file (ORB-SLAM3's YAML, read by io/settings_yaml.h).

#include "fuzz/targets.h"
#include "hoidslam/io/settings.h"

namespace hoidslam::fuzz {

void FuzzSettings(Bytes input) {
  const std::filesystem::path path = ScratchDir() / "settings.yaml";
  WriteBytes(path, input);
  const auto settings = ParseOrReject([&] { return io::LoadSettings(path); }, path.string());
  if (!settings) return;
  // What a file gives must pass the checks that settings built in code pass (ranges, finite numbers).
  try {
    settings->Check();
  } catch (const core::InputError& error) {
    throw ContractViolation(std::string("accepted settings fail Settings::Check: ") + error.what());
  }
}

}  // namespace hoidslam::fuzz
