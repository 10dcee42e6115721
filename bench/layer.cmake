# The layer's CPU frame path per eye at FOVE resolution (select + trace with a
# constant engine + interpolate + TAA), excluding Vulkan upload (measured by
# hello_foveated --json per frame instead).
add_executable(layer_bench ${CMAKE_CURRENT_SOURCE_DIR}/layer_bench.cpp)
target_link_libraries(layer_bench PRIVATE foveart::foveation benchmark::benchmark)
foveart_target_defaults(layer_bench)
