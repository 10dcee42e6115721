# The layer's public header as an application sees it: `cmake --install` the build
# into a fresh prefix, then compile a one-file C client and a one-file C++ client
# with -I<prefix>/include and no other include path. Fails when the installed
# header includes something that was not installed beside it.
#   cmake -DBUILD_DIR=<build> -DWORK_DIR=<scratch> -DC_COMPILER=<cc> -DCXX_COMPILER=<c++>
#         -P installed_header_test.cmake
foreach(var BUILD_DIR WORK_DIR C_COMPILER CXX_COMPILER)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "installed_header_test.cmake: pass -D${var}=...")
  endif()
endforeach()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD_DIR} --prefix ${prefix} failed (${rc}):\n${out}")
endif()

# Only the prefix: no include path may come from the environment either.
foreach(var CPATH C_INCLUDE_PATH CPLUS_INCLUDE_PATH)
  unset(ENV{${var}})
endforeach()

# Uses a type of the extension header and one of foveation/ray_trace.h, which it includes.
set(client_source [=[
#include <layer/XR_FOVEART_foveated_ray_tracing.h>

static int32_t trace_rays(void* user_data, const FoveartRayBatch* batch) {
  (void)user_data;
  return batch != 0 && batch->ray_count > 0 ? FOVEART_RESULT_SUCCESS : FOVEART_RESULT_ERROR_INVALID_ARGUMENT;
}

static XrFoveatedRendererCreateInfoFOVEART info;

int main(void) {
  info.type = XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART;
  info.traceRays = &trace_rays;
  return info.traceRays == 0;
}
]=])

foreach(lang c cpp)
  if(lang STREQUAL "c")
    set(compiler ${C_COMPILER})
    set(std -std=c11)
  else()
    set(compiler ${CXX_COMPILER})
    set(std -std=c++17)
  endif()
  file(WRITE ${WORK_DIR}/client.${lang} "${client_source}")
  set(command ${compiler} ${std} -Wall -Wextra -Werror -I${prefix}/include
      -c ${WORK_DIR}/client.${lang} -o ${WORK_DIR}/client_${lang}.o)
  execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    string(JOIN " " shown ${command})
    message(FATAL_ERROR "a ${lang} client of the installed header does not compile:\n${shown}\n${out}")
  endif()
endforeach()
message(STATUS "C and C++ clients compile against ${prefix}/include alone")
