# The lab's own costs: the perceptual metric per FOVE eye (the price list runs it per setting).
add_executable(eval_bench ${CMAKE_CURRENT_SOURCE_DIR}/eval_bench.cpp)
target_link_libraries(eval_bench PRIVATE foveart::eval benchmark::benchmark)
foveart_target_defaults(eval_bench)
