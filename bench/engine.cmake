# Sample engine benchmarks (issue 4).
if(TARGET foveart_engine AND TARGET foveart_fovea_render)
  add_executable(engine_bench ${CMAKE_CURRENT_SOURCE_DIR}/engine_bench.cpp)
  foveart_target_defaults(engine_bench)
  target_link_libraries(engine_bench PRIVATE foveart_engine foveart_fovea_render benchmark::benchmark)
  if(TARGET foveart_foveation)
    target_compile_definitions(engine_bench PRIVATE FOVEART_HAVE_FOVEATION=1)
  endif()
endif()
