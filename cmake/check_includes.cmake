# Fails when a target's sources include a header of a module it does not declare.
#   cmake -DMAP=build/seamap_modules.cmake -DMODULE=seamap_detect [-DSTAMP=file] -P cmake/check_includes.cmake
# MAP (written by cmake/SeamapModules.cmake) sets SEAMAP_SOURCE_DIR, SEAMAP_TARGETS
# and, per target T, SEAMAP_DIRS_T (the folders it owns), SEAMAP_SEES_T (the
# modules it may include: itself and its declared ones), SEAMAP_DEPS_T (the
# modules in its DEPS: one of its files must include each, except in targets
# named *_tests, whose DEPS carry test helpers) and SEAMAP_FILES_T
# (the files to read: its sources and the headers in its folders).
# An include is checked when its first folder is the first folder of some
# module (core/, server/, cli/, tests/...); its module is the one owning the
# folder that holds the header. Other includes (<vector>, <opencv2/...>) pass.
cmake_minimum_required(VERSION 3.18)
foreach(var MAP MODULE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_includes: -D${var}=... is required")
  endif()
endforeach()
include(${MAP})
if(NOT MODULE IN_LIST SEAMAP_TARGETS)
  message(FATAL_ERROR "check_includes: ${MODULE} is not a declared module (${MAP})")
endif()

set(roots)
foreach(t IN LISTS SEAMAP_TARGETS)
  foreach(dir IN LISTS SEAMAP_DIRS_${t})
    set("owner_${dir}" ${t})
    string(REGEX MATCH "^[^/]+" root "${dir}")
    list(APPEND roots ${root})
  endforeach()
endforeach()
list(REMOVE_DUPLICATES roots)

set(include_regex "^[ \t]*#[ \t]*include[ \t]*[<\"]([^\">]+)[\">]")
set(problems "")
set(used "")
foreach(file IN LISTS SEAMAP_FILES_${MODULE})
  file(STRINGS ${file} include_lines REGEX "${include_regex}")
  foreach(line IN LISTS include_lines)
    string(REGEX MATCH "${include_regex}" _ "${line}")
    set(header "${CMAKE_MATCH_1}")
    string(REGEX MATCH "^[^/]+" root "${header}")
    if(NOT root IN_LIST roots OR header STREQUAL root)
      continue()
    endif()
    get_filename_component(header_dir "${header}" DIRECTORY)
    set(owner "${owner_${header_dir}}")
    list(APPEND used ${owner})
    if(owner AND owner IN_LIST SEAMAP_SEES_${MODULE})
      continue()
    endif()
    # Where: the first line holding this include.
    file(READ ${file} content)
    string(FIND "${content}" "${line}" at)
    string(SUBSTRING "${content}" 0 ${at} before)
    string(REGEX MATCHALL "\n" newlines "${before}")
    list(LENGTH newlines line_number)
    math(EXPR line_number "${line_number} + 1")
    file(RELATIVE_PATH where ${SEAMAP_SOURCE_DIR} ${file})
    string(STRIP "${line}" line)
    if(owner)
      string(APPEND problems "${where}:${line_number}: ${line}: ${header} belongs to ${owner}, "
                             "which ${MODULE} does not declare: add ${owner} to its DEPS in CMakeLists.txt "
                             "(or drop the include)\n")
    else()
      string(APPEND problems "${where}:${line_number}: ${line}: ${header_dir}/ is no declared module's folder, "
                             "so ${MODULE} may not include it (declare the folder as a module, or drop the include)\n")
    endif()
  endforeach()
endforeach()

if(NOT MODULE MATCHES "_tests$")
  foreach(dep IN LISTS SEAMAP_DEPS_${MODULE})
    if(NOT dep IN_LIST used)
      string(APPEND problems "${MODULE} declares ${dep} in its DEPS but none of its files includes a header of it: "
                             "drop ${dep} from its DEPS in CMakeLists.txt\n")
    endif()
  endforeach()
endif()

if(problems)
  # NOTICE prints the lines as they are (an error's text would be rewrapped).
  message(NOTICE "${problems}")
  message(FATAL_ERROR "${MODULE}'s includes and its declared module dependencies disagree (above)")
endif()
if(DEFINED STAMP)
  get_filename_component(stamp_dir ${STAMP} DIRECTORY)
  file(MAKE_DIRECTORY ${stamp_dir})
  file(TOUCH ${STAMP})
endif()
