# Every third-party dependency, found once. All come from Debian 12 packages
# (scripts/setup.sh installs them). Modules link the imported targets below.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(Eigen3 3.4 CONFIG REQUIRED)
find_package(nanoflann CONFIG REQUIRED)
find_package(nlohmann_json 3 CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
pkg_check_modules(PLPLOT REQUIRED IMPORTED_TARGET plplot-c++)

if(FOVEART_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
endif()
if(FOVEART_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)
endif()
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)
