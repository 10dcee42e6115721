// The one rule for what is wrong with an input path.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "foveation/input_file.hpp"

namespace foveart::foveation {
namespace {

TEST(InputFile, NamesAMissingPathAndADirectoryAndPassesWhatCanBeRead) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  EXPECT_EQ(input_file_problem(dir / "foveart_no_such_input.csv"), "no such file");
  EXPECT_EQ(input_file_problem(dir), "a directory, not a file");
  const std::filesystem::path file = dir / "foveart_input_file_test.txt";
  std::ofstream(file) << "x";
  EXPECT_EQ(input_file_problem(file), "");
  std::filesystem::remove(file);
  EXPECT_EQ(input_file_problem("/dev/null"), "") << "a device or pipe is the reader's to judge";
}

}  // namespace
}  // namespace foveart::foveation
