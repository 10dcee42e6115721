// The lab's options beside a render's (lab_options.hpp).
#include <eval/lab_options.hpp>

#include <render_view/display_options.hpp>

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <filesystem>

namespace foveart::eval {

bool check_reference_choice(const ReferenceChoice& r, std::string* error) {
  if (!r.spp.empty() && r.spp != "auto") {
    char* end = nullptr;
    const long n = std::strtol(r.spp.c_str(), &end, 10);
    if (end == r.spp.c_str() || *end != '\0' || n < 2 || n > 65536 || n % 2 != 0 || (n > 16 && n % 16 != 0)) {
      *error = "--reference-spp must be auto or rays per pixel 2, 4, ..., 16 or a multiple of 16 up to 65536, got '" +
               r.spp + "'";
      return false;
    }
  }
  if (!r.spp.empty() && !r.file.empty()) {
    *error = "give --reference-spp or --reference, not both";
    return false;
  }
  return true;
}

std::string reference_cache_dir(const ReferenceChoice& r, const std::string& cache_dir) {
  if (!r.cache.empty()) return r.cache;
  if (!cache_dir.empty()) return (std::filesystem::path(cache_dir) / "reference").string();
  return "";
}

void add_reference_options(CLI::App* cmd, ReferenceChoice* reference, bool with_file) {
  cmd->add_option("--reference-spp", reference->spp,
                  "Errors against a converged full render: 'auto' (convergence check) or rays per pixel N");
  if (with_file) cmd->add_option("--reference", reference->file, "Errors against this linear-RGB PFM of the view");
  cmd->add_option("--reference-cache", reference->cache, "Reference cache directory (default: CACHE_DIR/reference)");
}

void add_temporal_lab_options(CLI::App* cmd, std::string* temporal, bool* mean_while_young, bool list) {
  cmd->add_option("--temporal", *temporal,
                  std::string(list ? "The foveated tracks' temporal variants, a list"
                                   : "The foveated frames' temporal variant") +
                      ": the product's off, image (an image history reprojected with the head) and rays (a render "
                      "cache of the traced rays), and the lab's restart (an image history restarted at every new "
                      "pose) and rays-kept (the render cache kept through saccades)" +
                      (list ? ", e.g. off,restart,image" : ""))
      ->capture_default_str();
  cmd->add_flag("--temporal-mean-while-young", *mean_while_young,
                "The k-th frame since a history's restart weighs max(1/k, alpha), the mean of a young history; "
                "default: alpha from the second frame on");
  render_view::add_renamed_option(cmd, "--taa", "--temporal");
  render_view::add_renamed_option(cmd, "--taa-mean-while-young", "--temporal-mean-while-young", /*flag=*/true);
}

}  // namespace foveart::eval
