# Builds tests/cmake/fixture and checks the include check's verdict.
#   cmake -DROOT=<source dir> -DWORK=<scratch build dir> -DCASE=rejects|accepts
#         -DGENERATOR=<cmake generator> -DCXX=<compiler> -P tests/cmake/expect_build.cmake
# rejects: seamap_b includes core/a/answer.h without declaring seamap_a, so the
#          build must fail, naming the file, line, include and missing module;
# accepts: seamap_b declares seamap_a, so it must build.
cmake_minimum_required(VERSION 3.18)
if(CASE STREQUAL "rejects")
  set(declare OFF)
elseif(CASE STREQUAL "accepts")
  set(declare ON)
else()
  message(FATAL_ERROR "expect_build: -DCASE=rejects|accepts")
endif()
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${ROOT}/tests/cmake/fixture -B ${WORK} -G ${GENERATOR}
                        -DCMAKE_CXX_COMPILER=${CXX} -DSEAMAP_ROOT=${ROOT} -DDECLARE_A=${declare}
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
    message(FATAL_ERROR "expect_build: an undeclared include built:\n${output}")
  endif()
  set(expected "core/b/question.cc:3: #include \"core/a/answer.h\": core/a/answer.h belongs to seamap_a, "
               "which seamap_b does not declare: add seamap_a to its DEPS")
  string(CONCAT expected ${expected})
  string(FIND "${output}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "expect_build: the build failed without saying\n  ${expected}\nit said:\n${output}")
  endif()
endif()
message(STATUS "expect_build: ${CASE}: as expected")
