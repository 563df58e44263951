# pip builds every install in a new temporary environment (/tmp/pip-build-env-XXXX), so the
# include directories of Eigen and pybind11 move from one `pip install` to the next, and with
# them every compile command and every header path: no compiled object of the first install
# could be recognised by the second. Copying those headers into the build tree, writing only
# files whose content changed, keeps the commands and the header paths stable, so the compiler
# cache (compiler_cache.cmake) recognises the objects of the previous install.

# Replace the include directories of the imported `target` by copies under the build tree.
function(corotate_stable_includes target name)
  get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT dirs)
    return()
  endif()
  set(stable "")
  set(index 0)
  foreach(dir IN LISTS dirs)
    if(NOT IS_ABSOLUTE "${dir}" OR NOT IS_DIRECTORY "${dir}")
      list(APPEND stable "${dir}")  # a generator expression or a missing path: left alone
      continue()
    endif()
    set(copy "${CMAKE_BINARY_DIR}/stable-include/${name}-${index}")
    file(GLOB_RECURSE files LIST_DIRECTORIES false RELATIVE "${dir}" "${dir}/*")
    foreach(file IN LISTS files)
      get_filename_component(parent "${copy}/${file}" DIRECTORY)
      file(MAKE_DIRECTORY "${parent}")
      if(CMAKE_VERSION VERSION_GREATER_EQUAL 3.21)
        file(COPY_FILE "${dir}/${file}" "${copy}/${file}" ONLY_IF_DIFFERENT)
      else()
        execute_process(COMMAND "${CMAKE_COMMAND}" -E copy_if_different "${dir}/${file}" "${copy}/${file}")
      endif()
    endforeach()
    list(APPEND stable "${copy}")
    math(EXPR index "${index} + 1")
  endforeach()
  set_property(TARGET ${target} PROPERTY INTERFACE_INCLUDE_DIRECTORIES "${stable}")
endfunction()
