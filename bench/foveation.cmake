add_executable(foveation_bench ${CMAKE_CURRENT_SOURCE_DIR}/foveation_bench.cpp)
target_link_libraries(foveation_bench PRIVATE foveart::foveation benchmark::benchmark)
foveart_target_defaults(foveation_bench)
