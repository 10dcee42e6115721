# Pacing on the real clock, measured rather than tested (the tests run these
# paths on virtual clocks): the simulated gaze provider's 120 Hz sampling thread
# and its stop(), and the simulated runtime's 70 Hz xrWaitFrame grid.
add_executable(pacing_bench ${CMAKE_CURRENT_SOURCE_DIR}/pacing_bench.cpp)
target_link_libraries(pacing_bench PRIVATE foveart::gaze foveart_sim_runtime_core benchmark::benchmark)
foveart_target_defaults(pacing_bench)
