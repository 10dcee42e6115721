// Writes the seed corpora of the three cache fuzz targets: real point set,
// neighbour table and interpolation table files for fuzz_cache_key.hpp's
// display. Usage: fuzz_make_cache_seeds CORPUS_DIR (writes CORPUS_DIR/<target>/seed).
#include <cstdio>
#include <filesystem>

#include "foveation/executor.hpp"
#include "foveation/foveated_view.hpp"
#include "fuzz_cache_key.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_make_cache_seeds CORPUS_DIR\n");
    return 2;
  }
  namespace fs = std::filesystem;
  namespace fv = foveart::foveation;
  const fs::path corpus = argv[1];
  const fs::path scratch = fs::temp_directory_path() / "foveart_fuzz_seeds";
  fs::remove_all(scratch);
  fv::Executor executor(1);
  fv::load_view_tables(scratch, foveart::fuzz::cache_key(0), foveart::fuzz::interp_options(), executor);
  const auto key = foveart::fuzz::cache_key(foveart::fuzz::kNeighbors);
  auto copy = [&](const fs::path& from, const char* target) {
    fs::create_directories(corpus / target);
    fs::copy_file(from, corpus / target / "seed", fs::copy_options::overwrite_existing);
  };
  copy(fv::point_set_cache_path(scratch, key), "fuzz_point_set_cache");
  copy(fv::neighbor_table_cache_path(scratch, key), "fuzz_neighbor_table_cache");
  for (const auto& e : fs::directory_iterator(scratch)) {
    if (e.path().filename().string().starts_with("interp")) copy(e.path(), "fuzz_interpolation_cache");
  }
  fs::remove_all(scratch);
  return 0;
}
