// What the lab's commands ask for beside a render's options
// (render_view::RenderOptions, shared with the product): the converged
// reference the images are measured against, and the lab's TAA modes.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace foveart::eval {

// The reference of `fovea-eval accuracy` and `motion`.
struct ReferenceChoice {
  // "" none, "auto" (the convergence check picks the count) or an even count of
  // rays per pixel: 2, 4, ..., 16 or a multiple of 16 up to 65536.
  std::string spp;
  std::string file;   // a linear-RGB PFM of the view's size instead (--reference FILE; a still view only)
  std::string cache;  // reference cache directory; empty: CACHE_DIR/reference, or none
};

// False and *error naming the option when the choice is not valid (a bad count, both a count and a file).
[[nodiscard]] bool check_reference_choice(const ReferenceChoice& reference, std::string* error);

// The reference cache directory: --reference-cache, else CACHE_DIR/reference, else "" (none).
std::string reference_cache_dir(const ReferenceChoice& reference, const std::string& cache_dir);

// --reference-spp and --reference-cache into *reference; with_file: --reference FILE too.
void add_reference_options(CLI::App* cmd, ReferenceChoice* reference, bool with_file);

// --taa (one of the lab's TAA modes, taa_modes.hpp, or with a list a comma-separated list of them)
// and --taa-mean-while-young.
void add_taa_lab_options(CLI::App* cmd, std::string* taa, bool* mean_while_young, bool list);

}  // namespace foveart::eval
