# Interpolation (NN, MSM, RBF), its cached tables, the per-frame gather, TAA and
# image metrics (issue 3). Included by foveation/CMakeLists.txt after
# foveart_foveation is defined.
target_sources(foveart_foveation PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/interpolation_weights.cpp
)
target_link_libraries(foveart_foveation PUBLIC Eigen3::Eigen PRIVATE PkgConfig::XXHASH Threads::Threads)
