# Sample engine benchmarks: ray throughput, per-effect cost, foveated against full.
add_executable(engine_bench ${CMAKE_CURRENT_SOURCE_DIR}/engine_bench.cpp)
foveart_target_defaults(engine_bench)
target_link_libraries(engine_bench PRIVATE foveart_engine benchmark::benchmark)
