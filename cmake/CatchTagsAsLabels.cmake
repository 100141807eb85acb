# Catch tags as ctest labels, for Catch2 2.x, whose Catch.cmake has no ADD_TAGS_AS_LABELS.
#
#   include(${PROJECT_SOURCE_DIR}/cmake/CatchTagsAsLabels.cmake)
#   catch_discover_tests(target ...)    # once or more, without TEST_PREFIX or TEST_SUFFIX
#   catch_tags_as_labels(target [TEST_SPEC spec] [WORKING_DIRECTORY dir])
#
# gives each ctest test that catch_discover_tests made of a test case the case's tags as its
# LABELS, lower-case as Catch compares them: `[zbuffer][steps]` becomes `steps;zbuffer`. TEST_SPEC
# selects the cases the discovery calls made tests of together (default: all but hidden ones); a
# case it selects that has no test is left alone. Like Catch's discovery, it runs after each build
# of the target (POST_BUILD): it asks the executable for its tags (--list-tags) and for the names
# under each (--list-test-names-only "[tag]"), and writes set_tests_properties() calls to a file that
# ctest includes after Catch's own. LABELS is replaced, so a label that catch_discover_tests set
# through PROPERTIES must be one of the case's tags (as `slow` is for `[slow]`): it then stays too
# when that file is missing.
#
# The same file is the POST_BUILD script, run as `cmake -D... -P CatchTagsAsLabels.cmake`.

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  # The test cases' names, one per line, as CatchAddTests.cmake reads them into ctest names.
  function(list_test_names out_keys spec)
    execute_process(
      COMMAND ${TEST_EXECUTOR} "${TEST_EXECUTABLE}" ${spec} --list-test-names-only
      OUTPUT_VARIABLE output
      RESULT_VARIABLE result
      WORKING_DIRECTORY "${TEST_WORKING_DIR}")
    if(NOT result MATCHES "^[0-9]+$")  # the exit code is the number of names
      message(FATAL_ERROR "Error running '${TEST_EXECUTABLE}' ${spec} --list-test-names-only:\n"
                          "  Result: ${result}\n  Output: ${output}\n")
    endif()
    string(REPLACE "\n" ";" output "${output}")
    set(keys "")
    foreach(name ${output})  # an MD5 each: a name may hold what a CMake list cannot
      string(MD5 key "${name}")
      set(name_${key} "${name}" PARENT_SCOPE)
      list(APPEND keys ${key})
    endforeach()
    set(${out_keys} ${keys} PARENT_SCOPE)
  endfunction()

  list_test_names(tested "${TEST_SPEC}")
  foreach(key IN LISTS tested)
    set(tested_${key} TRUE)
  endforeach()

  execute_process(
    COMMAND ${TEST_EXECUTOR} "${TEST_EXECUTABLE}" ${TEST_SPEC} --list-tags
    OUTPUT_VARIABLE output
    RESULT_VARIABLE result
    WORKING_DIRECTORY "${TEST_WORKING_DIR}")
  if(NOT result MATCHES "^[0-9]+$")  # the exit code is the number of tags
    message(FATAL_ERROR "Error running '${TEST_EXECUTABLE}' ${TEST_SPEC} --list-tags:\n"
                        "  Result: ${result}\n  Output: ${output}\n")
  endif()
  # A tag's line: its count, then its spellings ("   3  [zbuffer]", "   2  [Slow][slow]").
  string(REPLACE "\n" ";" output "${output}")
  set(tags "")
  foreach(line IN LISTS output)
    if(line MATCHES "^ *[0-9]+  \\[(.*)$")
      string(FIND "${CMAKE_MATCH_1}" "]" end)
      if(end LESS 1)
        message(WARNING "${TEST_EXECUTABLE}: no label from the tag line '${line}'")
        continue()
      endif()
      string(SUBSTRING "${CMAKE_MATCH_1}" 0 ${end} tag)
      string(TOLOWER "${tag}" tag)
      list(APPEND tags "${tag}")
    endif()
  endforeach()

  foreach(tag IN LISTS tags)
    list_test_names(tagged "[${tag}]")
    foreach(key IN LISTS tagged)
      if(tested_${key})
        list(APPEND labels_${key} "${tag}")
      endif()
    endforeach()
  endforeach()

  set(script "")
  foreach(key IN LISTS tested)
    if(DEFINED labels_${key})
      string(APPEND script "set_tests_properties([==[${name_${key}}]==] PROPERTIES LABELS [==[${labels_${key}}]==])\n")
    endif()
  endforeach()
  file(WRITE "${LABELS_FILE}" "${script}")
  return()
endif()

function(catch_tags_as_labels target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "TEST_SPEC;WORKING_DIRECTORY" "")
  if(NOT DEFINED arg_TEST_SPEC)
    set(arg_TEST_SPEC "~[.]")
  endif()
  if(NOT arg_WORKING_DIRECTORY)
    set(arg_WORKING_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}")
  endif()
  set(labels_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_labels.cmake")
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_labels_include.cmake")
  get_property(emulator TARGET ${target} PROPERTY CROSSCOMPILING_EMULATOR)
  add_custom_command(
    TARGET ${target} POST_BUILD
    BYPRODUCTS "${labels_file}"
    COMMAND "${CMAKE_COMMAND}"
            -D "TEST_EXECUTABLE=$<TARGET_FILE:${target}>"
            -D "TEST_EXECUTOR=${emulator}"
            -D "TEST_WORKING_DIR=${arg_WORKING_DIRECTORY}"
            -D "TEST_SPEC=${arg_TEST_SPEC}"
            -D "LABELS_FILE=${labels_file}"
            -P "${CMAKE_CURRENT_FUNCTION_LIST_FILE}"
    VERBATIM)
  file(WRITE "${include_file}"
       "if(EXISTS \"${labels_file}\")\n"
       "  include(\"${labels_file}\")\n"
       "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()
