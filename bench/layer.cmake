# The layer's CPU frame path per eye at FOVE resolution (select + trace with a
# constant engine + interpolate + TAA), excluding Vulkan upload (measured by
# hello_foveated --json per frame instead).
add_executable(layer_bench ${CMAKE_CURRENT_SOURCE_DIR}/layer_bench.cpp)
target_link_libraries(layer_bench PRIVATE foveart::foveation benchmark::benchmark)
foveart_target_defaults(layer_bench)

# Reconstruction + TAA per eye on the CPU and the GPU path in one run
# (scripts/bench_gpu.sh; lavapipe when the machine has no GPU).
# Not a Google Benchmark program: its own table of both paths (hence not *_bench).
add_executable(reconstruction_paths ${CMAKE_CURRENT_SOURCE_DIR}/reconstruction_paths.cpp)
target_link_libraries(reconstruction_paths PRIVATE foveart::layer_impl CLI11::CLI11)
target_include_directories(reconstruction_paths PRIVATE ${PROJECT_SOURCE_DIR}/tests/common  # headless_vulkan.hpp
                                                        ${PROJECT_SOURCE_DIR}/samples/gpu_engine/include)  # its messenger
foveart_target_defaults(reconstruction_paths)
# GCC 12's false -Wnull-dereference inside CLI11's detail::split (as in tools/fovea).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/reconstruction_paths.cpp PROPERTIES COMPILE_OPTIONS "-Wno-null-dereference")
endif()

# One eye's full and foveated frame on the GPU sample engine, per stage, in one
# run (scripts/bench_gpu.sh): the device trace end to end.
add_executable(gpu_frame ${CMAKE_CURRENT_SOURCE_DIR}/gpu_frame.cpp)
target_link_libraries(gpu_frame PRIVATE foveart::layer_impl foveart::gpu_engine foveart::engine CLI11::CLI11
                                        nlohmann_json::nlohmann_json)
target_include_directories(gpu_frame PRIVATE ${PROJECT_SOURCE_DIR}/tests/common)  # headless_vulkan.hpp
foveart_target_defaults(gpu_frame)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/gpu_frame.cpp PROPERTIES COMPILE_OPTIONS "-Wno-null-dereference")
endif()

# The whole frame, both eyes, from hello_foveated's runs under the counting Vulkan
# layer (scripts/bench_gpu.sh): times, submitted work, rays, bytes, prediction.
add_executable(gpu_frame_report ${CMAKE_CURRENT_SOURCE_DIR}/frame_report.cpp)
target_link_libraries(gpu_frame_report PRIVATE foveart::foveation CLI11::CLI11 nlohmann_json::nlohmann_json)
target_include_directories(gpu_frame_report PRIVATE ${PROJECT_SOURCE_DIR}/tests/vk_count)  # vk_records.hpp
foveart_target_defaults(gpu_frame_report)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/frame_report.cpp PROPERTIES COMPILE_OPTIONS "-Wno-null-dereference")
endif()
