# Interpolation (NN, MSM, RBF), its cached tables, the per-frame gather, TAA and
# image metrics (issue 3). Included by foveation/CMakeLists.txt after
# foveart_foveation is defined.
target_sources(foveart_foveation PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/interpolation_weights.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/interpolation_table.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/gather.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/gather_layout.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/interpolation_cache.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/taa.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/image_metrics.cpp
)
target_link_libraries(foveart_foveation PUBLIC Eigen3::Eigen PRIVATE PkgConfig::XXHASH Threads::Threads)
# TAA's row loop is written to vectorise across pixels: let GCC do it (-O3) and
# use the sqrt instruction without errno handling. Neither changes a result.
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/src/taa.cpp PROPERTIES COMPILE_OPTIONS "-O3;-fno-math-errno")
