# The simulated FOVE 0 runtime's manifest (XR_RUNTIME_JSON points at it).
# Build tree: <build>/manifests/foveart_sim_runtime.json -> ../lib/libfoveart_sim_runtime.so
# Install:    <prefix>/share/foveart/manifests/foveart_sim_runtime.json -> relative path to
#             <prefix>/lib/.../libfoveart_sim_runtime.so (the loader resolves it from the
#             manifest's folder).
set(FOVEART_SIM_RUNTIME_LIBRARY_NAME libfoveart_sim_runtime.so)

file(RELATIVE_PATH FOVEART_SIM_RUNTIME_LIBRARY_PATH ${FOVEART_MANIFEST_DIR}
     ${CMAKE_LIBRARY_OUTPUT_DIRECTORY}/${FOVEART_SIM_RUNTIME_LIBRARY_NAME})
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/foveart_sim_runtime.json.in
               ${FOVEART_MANIFEST_DIR}/foveart_sim_runtime.json @ONLY)

set(_manifest_install_dir ${CMAKE_INSTALL_DATADIR}/foveart/manifests)
file(RELATIVE_PATH FOVEART_SIM_RUNTIME_LIBRARY_PATH
     /prefix/${_manifest_install_dir} /prefix/${CMAKE_INSTALL_LIBDIR}/${FOVEART_SIM_RUNTIME_LIBRARY_NAME})
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/foveart_sim_runtime.json.in
               ${CMAKE_CURRENT_BINARY_DIR}/install/foveart_sim_runtime.json @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/install/foveart_sim_runtime.json
        DESTINATION ${_manifest_install_dir} COMPONENT sim_runtime)
unset(FOVEART_SIM_RUNTIME_LIBRARY_PATH)
