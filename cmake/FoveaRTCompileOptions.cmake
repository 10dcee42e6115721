# Warnings and sanitizers for every FoveaRT target.
#   foveart_target_defaults(<target>) applies them; third-party headers are
#   included as SYSTEM so their warnings stay out of ours.

set(FOVEART_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Wnull-dereference
    -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
# In a unity batch every source but the batch's own is an included file, where
# GCC warns of a class with a member of an unnamed-namespace type as if in a
# header (the warning guards headers against ODR violations; these are sources).
if(FOVEART_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  list(APPEND FOVEART_WARNINGS -Wno-subobject-linkage)
endif()
set(FOVEART_C_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)

# Sanitizer builds compile at FOVEART_SANITIZE_OPT, after the build type's flags so
# it wins: -O1 as the sanitizers' own docs advise, -g1 keeps the line tables their
# stack traces need. Together they halve the suite's compile time against -O2 -g.
set(FOVEART_SANITIZE_OPT "-O1;-g1" CACHE STRING "Optimisation and debug flags of sanitizer builds")

if(FOVEART_SANITIZE)
  string(REPLACE ";" "," _san "${FOVEART_SANITIZE}")
  add_compile_options(${FOVEART_SANITIZE_OPT}
    -fsanitize=${_san} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${_san})
  message(STATUS "FoveaRT: sanitizers ${_san}")
endif()

# Command-line, configuration and report glue (argument parsing, JSON, tables)
# does no per-pixel or per-ray work, yet its CLI11 and JSON templates are the
# costliest files to compile: sanitizer builds compile it unoptimised, about
# half the time of FOVEART_SANITIZE_OPT. foveart_glue_target for a target that
# is all glue (its sources still share unity batches); foveart_glue_sources for
# single files of other targets (call from the sources' own directory), which
# compile alone.
function(foveart_glue_target target)
  if(FOVEART_SANITIZE)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()

function(foveart_glue_sources)
  # Alone in every build, so that the unity batches are the same with and without sanitizers.
  set_property(SOURCE ${ARGN} PROPERTY SKIP_UNITY_BUILD_INCLUSION ON)
  if(FOVEART_SANITIZE)
    set_property(SOURCE ${ARGN} APPEND PROPERTY COMPILE_OPTIONS -O0)
  endif()
endfunction()

function(foveart_target_defaults target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:${FOVEART_WARNINGS}>
    $<$<COMPILE_LANGUAGE:C>:${FOVEART_C_WARNINGS}>
    $<$<BOOL:${FOVEART_WERROR}>:-Werror>)
endfunction()
