// The lab's options beside a render's (lab_options.hpp).
#include <eval/lab_options.hpp>

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

void add_taa_lab_options(CLI::App* cmd, std::string* taa, bool* mean_while_young, bool list) {
  cmd->add_option("--taa", *taa,
                  std::string(list ? "TAA modes of the foveated tracks, a list" : "TAA mode of the foveated frames") +
                      ": off, restart (on every pose change), reproject (follows the head; the layer's \"temporal\": "
                      "\"image\"), cache (the traced rays kept in a render cache; \"rays\"), cache-kept (its rays "
                      "kept through saccades)" +
                      (list ? ", e.g. off,restart,reproject" : ""))
      ->capture_default_str();
  cmd->add_flag("--taa-mean-while-young", *mean_while_young,
                "TAA: the k-th frame since a restart weighs max(1/k, alpha), the mean of a young history; "
                "default: alpha from the second frame on");
}

}  // namespace foveart::eval
