# `fovea interpolate` and `fovea reconstruct` (issue 3), linked into the fovea
# tool by tools/fovea/CMakeLists.txt (include(interp_commands.cmake)).
add_library(foveart_fovea_interp_cmds STATIC
  ${CMAKE_CURRENT_LIST_DIR}/cmd_interpolate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cmd_reconstruct.cpp)
target_include_directories(foveart_fovea_interp_cmds PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(foveart_fovea_interp_cmds
  PUBLIC foveart::foveation CLI11::CLI11
  PRIVATE nlohmann_json::nlohmann_json PkgConfig::STB nanoflann::nanoflann)
foveart_target_defaults(foveart_fovea_interp_cmds)
