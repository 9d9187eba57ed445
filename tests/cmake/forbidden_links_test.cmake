# cmake -DPOET_SOURCE_DIR=<source> -DWORK_DIR=<scratch> -P forbidden_links_test.cmake
# poet_forbid_links (cmake/ForbiddenLinks.cmake) passes a clean library and fails the configure, naming the
# cause, when the library links a forbidden target directly or through another, or includes a forbidden header
# directly or through a header of another folder.

function(configure_fixture violation out_result out_output)
  set(build "${WORK_DIR}/${violation}")
  file(REMOVE_RECURSE "${build}")
  execute_process(COMMAND ${CMAKE_COMMAND} -S "${POET_SOURCE_DIR}/tests/cmake/forbidden_links_fixture" -B "${build}"
                          -DPOET_SOURCE_DIR=${POET_SOURCE_DIR} -DVIOLATION=${violation}
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  set(${out_result} ${result} PARENT_SCOPE)
  set(${out_output} "${output}" PARENT_SCOPE)
endfunction()

configure_fixture(none result output)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "a library with no forbidden link was refused:\n${output}")
endif()

foreach(case "link;must not link json_like" "transitive_link;must not link json_like"
             "include;includes a forbidden header" "transitive_include;deeper.h includes a forbidden header")
  list(GET case 0 violation)
  list(GET case 1 expected)
  configure_fixture(${violation} result output)
  if(result EQUAL 0)
    message(FATAL_ERROR "${violation}: the configure passed; it must fail")
  endif()
  string(REGEX REPLACE "[ \t\r\n]+" " " flat "${output}")  # CMake wraps its messages
  string(FIND "${flat}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${violation}: the configure failed without saying \"${expected}\":\n${output}")
  endif()
  message(STATUS "${violation}: refused (${expected})")
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
