// Config search chain, per-application sections and bad-input warnings.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "config.hpp"

namespace foveart::layer {
namespace {

namespace fs = std::filesystem;

class ConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("foveart_config_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    env_["HOME"] = (root_ / "home").string();
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path write(const fs::path& relative, const std::string& text) {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path;
  }
  GetEnvFn env() const {
    return [this](const char* name) -> std::optional<std::string> {
      auto it = env_.find(name);
      if (it == env_.end()) return std::nullopt;
      return it->second;
    };
  }
  static bool any_warning_contains(const ConfigResult& r, const std::string& needle) {
    for (const auto& w : r.warnings) {
      if (w.find(needle) != std::string::npos) return true;
    }
    return false;
  }

  fs::path root_;
  std::map<std::string, std::string> env_;
};

TEST_F(ConfigTest, NoFileGivesDefaultsWithoutWarnings) {
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  const auto r = load_config("app", env());
  EXPECT_TRUE(r.config.enabled);
  EXPECT_EQ(r.config.k, LayerConfig{}.k);
  EXPECT_TRUE(r.warnings.empty());
}

TEST_F(ConfigTest, FoveartConfigWinsOverXdg) {
  const auto explicit_path = write("explicit.json", R"({"k": 7})");
  write("xdg/foveart/config.json", R"({"k": 9})");
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  env_["FOVEART_CONFIG"] = explicit_path.string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, 7u);
  EXPECT_EQ(r.path, explicit_path.string());
}

TEST_F(ConfigTest, MissingFoveartConfigWarnsAndFallsBackToXdg) {
  write("xdg/foveart/config.json", R"({"k": 9})");
  env_["XDG_CONFIG_HOME"] = (root_ / "xdg").string();
  env_["FOVEART_CONFIG"] = (root_ / "nope.json").string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, 9u);
  EXPECT_TRUE(any_warning_contains(r, "nope.json"));
}

TEST_F(ConfigTest, HomeDotConfigWhenXdgUnset) {
  write("home/.config/foveart/config.json", R"({"rays_per_point": 4})");
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.rays_per_point, 4u);
}

TEST_F(ConfigTest, ApplicationSectionOverridesTopLevel) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"k": 3, "taa": true,
      "applications": {"hello_xr": {"k": 12, "taa": false}, "other": {"k": 1}}})").string();
  const auto hello = load_config("hello_xr", env());
  EXPECT_EQ(hello.config.k, 12u);
  EXPECT_FALSE(hello.config.taa);
  const auto unnamed = load_config("someone_else", env());
  EXPECT_EQ(unnamed.config.k, 3u);
  EXPECT_TRUE(unnamed.config.taa);
}

TEST_F(ConfigTest, BadValueWarnsNamingKeyAndKeepsDefault) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"k": "many", "density_scale": -1, "interpolation": "cubic",
      "log_level": "loud", "rays_per_point": 1000})").string();
  const auto r = load_config("app", env());
  const LayerConfig defaults;
  EXPECT_EQ(r.config.k, defaults.k);
  EXPECT_EQ(r.config.density_scale, defaults.density_scale);
  EXPECT_EQ(r.config.interpolation, defaults.interpolation);
  EXPECT_EQ(r.config.log_level, defaults.log_level);
  EXPECT_EQ(r.config.rays_per_point, defaults.rays_per_point);
  for (const char* key : {"'k'", "'density_scale'", "'interpolation'", "'log_level'", "'rays_per_point'"}) {
    EXPECT_TRUE(any_warning_contains(r, key)) << key;
  }
}

TEST_F(ConfigTest, UnknownKeyWarns) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"kk": 3})").string();
  const auto r = load_config("app", env());
  EXPECT_TRUE(any_warning_contains(r, "'kk'"));
}

TEST_F(ConfigTest, InvalidJsonWarnsAndUsesDefaults) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"k": 3,)").string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.k, LayerConfig{}.k);
  EXPECT_TRUE(any_warning_contains(r, "not valid JSON"));
}

TEST_F(ConfigTest, FoveartDisableWinsOverFile) {
  env_["FOVEART_CONFIG"] = write("c.json", R"({"enabled": true})").string();
  env_["FOVEART_DISABLE"] = "1";
  EXPECT_FALSE(load_config("app", env()).config.enabled);
  env_["FOVEART_DISABLE"] = "0";
  EXPECT_TRUE(load_config("app", env()).config.enabled);
}

TEST_F(ConfigTest, LogSettingsAreRead) {
  env_["FOVEART_CONFIG"] =
      write("c.json", R"({"log_level": "debug", "log_file": "/tmp/foveart.log"})").string();
  const auto r = load_config("app", env());
  EXPECT_EQ(r.config.log_level, LogLevel::Debug);
  EXPECT_EQ(r.config.log_file, "/tmp/foveart.log");
}

}  // namespace
}  // namespace foveart::layer
