# Builds tests/cmake/fixture and checks the include check's verdict.
#   cmake -DROOT=<source dir> -DWORK=<scratch build dir> -DCASE=rejects|accepts|unused
#         -DGENERATOR=<cmake generator> -DCXX=<compiler> -P tests/cmake/expect_build.cmake
# rejects: seamap_b includes core/a/answer.h without declaring seamap_a, so the
#          build must fail, naming the file, line, include and missing module;
# accepts: seamap_b declares seamap_a, so it must build;
# unused:  seamap_c declares seamap_a and includes none of it, so the build
#          must fail, naming both.
cmake_minimum_required(VERSION 3.18)
set(unused OFF)
if(CASE STREQUAL "rejects")
  set(declare OFF)
  set(expected "core/b/question.cc:3: #include \"core/a/answer.h\": core/a/answer.h belongs to seamap_a, "
               "which seamap_b does not declare: add seamap_a to its DEPS")
elseif(CASE STREQUAL "accepts")
  set(declare ON)
elseif(CASE STREQUAL "unused")
  set(declare ON)
  set(unused ON)
  set(expected "seamap_c declares seamap_a in its DEPS but none of its files includes a header of it")
else()
  message(FATAL_ERROR "expect_build: -DCASE=rejects|accepts|unused")
endif()
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${ROOT}/tests/cmake/fixture -B ${WORK} -G ${GENERATOR}
                        -DCMAKE_CXX_COMPILER=${CXX} -DSEAMAP_ROOT=${ROOT} -DDECLARE_A=${declare} -DDECLARE_UNUSED=${unused}
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "expect_build: the fixture did not configure:\n${output}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}
                RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(CASE STREQUAL "accepts")
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "expect_build: a declared include failed the build:\n${output}")
  endif()
else()
  if(status EQUAL 0)
    message(FATAL_ERROR "expect_build: a build whose includes disagree with its DEPS (${CASE}) passed:\n${output}")
  endif()
  string(CONCAT expected ${expected})
  string(FIND "${output}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "expect_build: the build failed without saying\n  ${expected}\nit said:\n${output}")
  endif()
endif()
message(STATUS "expect_build: ${CASE}: as expected")
