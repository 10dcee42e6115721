# Interpolation benchmarks: thesis Table 2 on this CPU.
add_executable(interp_bench ${CMAKE_CURRENT_SOURCE_DIR}/interp_bench.cpp)
target_link_libraries(interp_bench PRIVATE foveart::foveation benchmark::benchmark)
foveart_target_defaults(interp_bench)
