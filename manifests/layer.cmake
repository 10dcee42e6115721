# Manifests of the API layer XR_APILAYER_FOVEART_foveated_ray_tracing.
#   build tree:   <build>/manifests/explicit/XR_APILAYER_FOVEART_foveated_ray_tracing.json  (XR_API_LAYER_PATH)
#                 <build>/manifests/implicit/XR_APILAYER_FOVEART_foveated_ray_tracing.json
#   cmake --install: <datadir>/openxr/1/api_layers/{explicit.d,implicit.d}/
# The implicit layer is off unless FOVEART_ENABLE_IMPLICIT_LAYER is set, and off
# whenever FOVEART_DISABLE_IMPLICIT_LAYER is set.
include(GNUInstallDirs)

set(_layer_name XR_APILAYER_FOVEART_foveated_ray_tracing)

# The extension's version as the manifests advertise it: the header's, one definition.
# A new version in the header configures the manifests again.
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
             ${PROJECT_SOURCE_DIR}/layer/include/layer/XR_FOVEART_foveated_ray_tracing.h)
file(STRINGS ${PROJECT_SOURCE_DIR}/layer/include/layer/XR_FOVEART_foveated_ray_tracing.h _spec_line
     REGEX "^#define XR_FOVEART_foveated_ray_tracing_SPEC_VERSION [0-9]+$")
string(REGEX REPLACE ".* ([0-9]+)$" "\\1" FOVEART_EXTENSION_SPEC_VERSION "${_spec_line}")
if(NOT FOVEART_EXTENSION_SPEC_VERSION MATCHES "^[0-9]+$")
  message(FATAL_ERROR "manifests: no XR_FOVEART_foveated_ray_tracing_SPEC_VERSION in the extension header")
endif()

foreach(kind IN ITEMS explicit implicit)
  if(kind STREQUAL "explicit")
    set(_template ${CMAKE_CURRENT_LIST_DIR}/${_layer_name}.json.in)
  else()
    set(_template ${CMAKE_CURRENT_LIST_DIR}/${_layer_name}_implicit.json.in)
  endif()
  # Build tree: the library where the build put it (generator expression).
  set(FOVEART_LAYER_LIBRARY_PATH "$<TARGET_FILE:foveart_layer>")
  configure_file(${_template} ${CMAKE_CURRENT_BINARY_DIR}/${kind}.build.json.in @ONLY)
  file(GENERATE OUTPUT ${FOVEART_MANIFEST_DIR}/${kind}/${_layer_name}.json
       INPUT ${CMAKE_CURRENT_BINARY_DIR}/${kind}.build.json.in)
  # Installed: the library in the standard OpenXR layer directory, named
  # relative to the manifest (the loader resolves it from the manifest's folder),
  # so `cmake --install --prefix` anywhere works.
  file(RELATIVE_PATH _relative /prefix/${CMAKE_INSTALL_DATAROOTDIR}/openxr/1/api_layers/${kind}.d
       /prefix/${CMAKE_INSTALL_LIBDIR}/openxr/1/api_layers)
  set(FOVEART_LAYER_LIBRARY_PATH "${_relative}/$<TARGET_FILE_NAME:foveart_layer>")
  configure_file(${_template} ${CMAKE_CURRENT_BINARY_DIR}/${kind}.install.json.in @ONLY)
  file(GENERATE OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/install/${kind}/${_layer_name}.json
       INPUT ${CMAKE_CURRENT_BINARY_DIR}/${kind}.install.json.in)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/install/${kind}/${_layer_name}.json
          DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/openxr/1/api_layers/${kind}.d)
endforeach()
