# Helpers every CMakeLists.txt below the root uses.

# Adds every immediate subfolder that has a CMakeLists.txt, sorted for a stable build order, so
# adding an area (a library, a service, a test folder) never means editing a shared list.
function(odonata_add_subdirectories)
  file(GLOB _areas LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT _areas)
  foreach(_area IN LISTS _areas)
    if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${_area} AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${_area}/CMakeLists.txt)
      add_subdirectory(${_area})
    endif()
  endforeach()
endfunction()

# Gives a common/ library its own include root, so `#include "<area>/x.hpp"` resolves only in
# targets that link that library: a header used without its library fails to compile instead
# of failing (or, worse, silently working) at link time. The root is a folder in the build tree
# holding one link, <area> → this source folder, since every area shares common/ as parent.
function(odonata_area_includes target visibility)
  get_filename_component(_area ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  set(_root ${CMAKE_BINARY_DIR}/include_roots/${_area})
  file(MAKE_DIRECTORY ${_root})
  if(NOT EXISTS ${_root}/${_area})
    file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR} ${_root}/${_area} SYMBOLIC)
  endif()
  target_include_directories(${target} ${visibility} ${_root})
endfunction()

# In the sanitizer build, turns UBSan's alignment and null checks back on for a library that reads
# bytes from outside as typed values (odonata_bus: datagrams, log files; odonata_io: CSV), where a
# misaligned read is the bug to catch. The rest of the tree leaves them out: it builds in 8.6 min
# instead of 10.5 on two cores (root CMakeLists).
function(odonata_sanitize_received_bytes target)
  if(ODONATA_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=alignment,null)
  endif()
endfunction()

# odonata_find_shared(VAR SUBDIR FILE...): the folder of the shared data beside the source tree
# (../shared/SUBDIR, a CI clone's copy) or the workplace's (/work/shared/SUBDIR) that holds every
# FILE, read in place; empty when neither does (the tests that need it are then not registered).
function(odonata_find_shared var subdir)
  set(_found "")
  foreach(_dir ${PROJECT_SOURCE_DIR}/../shared/${subdir} /work/shared/${subdir})
    get_filename_component(_dir ${_dir} ABSOLUTE)
    set(_all TRUE)
    foreach(_file ${ARGN})
      if(NOT EXISTS ${_dir}/${_file})
        set(_all FALSE)
      endif()
    endforeach()
    if(NOT _found AND _all)
      set(_found ${_dir})
    endif()
  endforeach()
  set(${var} ${_found} PARENT_SCOPE)
endfunction()
