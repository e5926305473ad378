# hovr: higher-order volume rendering for VTK.
#
# hovr_add_python_test(<name> [SCRIPT <script>] [ARGS ...] [LABELS ...] [TIMEOUT <s>]
#                      [COST <s>]): the
# Python test Test<...>.py of the calling Testing/Python folder as ctest "hovrPython-<name>",
# run with the build's hovr package and the shared test helpers (Testing/Python/hovrtesting.py)
# on the path. A script exits 0 on success, 125 when its data is missing (reported as
# skipped). SCRIPT (default: the test's name) runs with ARGS, so that one script can be
# several tests. COST, the test's usual seconds, lets ctest -j start the longest tests first on
# a clean build (which has no timings of earlier runs), so that none of them ends the run alone.
# Rendering tests need a display; ./hovr test runs ctest under Xvfb when there is none.
set(hovr_python_test_environment
  "PYTHONPATH=${CMAKE_BINARY_DIR}/${hovr_python_destination}:${PROJECT_SOURCE_DIR}/Testing/Python"
  "HOVR_ROOT=${PROJECT_SOURCE_DIR}"
  "HOVR_BUILD=${CMAKE_BINARY_DIR}")

function (hovr_add_python_test name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "TIMEOUT;SCRIPT;COST" "LABELS;ARGS")
  if (NOT arg_SCRIPT)
    set(arg_SCRIPT "${name}")
  endif ()
  add_test(NAME "hovrPython-${name}"
    COMMAND "${Python3_EXECUTABLE}" "${CMAKE_CURRENT_SOURCE_DIR}/${arg_SCRIPT}.py" ${arg_ARGS})
  if (NOT arg_TIMEOUT)
    set(arg_TIMEOUT 300)
  endif ()
  set_tests_properties("hovrPython-${name}" PROPERTIES
    ENVIRONMENT "${hovr_python_test_environment}"
    SKIP_RETURN_CODE 125
    TIMEOUT "${arg_TIMEOUT}"
    LABELS "hovr;python;${arg_LABELS}")
  if (arg_COST)
    set_tests_properties("hovrPython-${name}" PROPERTIES COST "${arg_COST}")
  endif ()
endfunction ()
