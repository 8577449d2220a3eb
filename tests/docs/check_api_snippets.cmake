# tests/docs/check_api_snippets.cmake — every code block in docs/API.md is a
# verbatim excerpt of a source file that the build compiles and a test runs.
#
#   cmake -DSOURCE_DIR=<octray source> -P tests/docs/check_api_snippets.cmake
#
# Each fenced block (```) must sit directly under a marker line
#   <!-- snippet: examples/FILE -->
# naming a file in examples/ that examples/CMakeLists.txt builds into a test
# (examples/consumer/* is built and run by the install.consumer test). The
# block's text, every character of every line, must occur in that file.
cmake_minimum_required(VERSION 3.21)

if(NOT DEFINED SOURCE_DIR)
  message(FATAL_ERROR "check_api_snippets.cmake: -DSOURCE_DIR=... is required")
endif()
set(doc_path "${SOURCE_DIR}/docs/API.md")
file(READ "${doc_path}" rest)
file(READ "${SOURCE_DIR}/examples/CMakeLists.txt" examples_cmake)

set(fence "```")
set(marker "<!-- snippet: ")
set(count 0)
set(errors "")
while(TRUE)
  string(FIND "${rest}" "${fence}" open_at)
  if(open_at EQUAL -1)
    break()
  endif()
  math(EXPR count "${count} + 1")
  # The line just above the opening fence must be the marker.
  string(SUBSTRING "${rest}" 0 ${open_at} before)
  string(FIND "${before}" "${marker}" marker_at REVERSE)
  set(file "")
  if(NOT marker_at EQUAL -1)
    string(SUBSTRING "${before}" ${marker_at} -1 marker_line)
    if(marker_line MATCHES "^<!-- snippet: ([^ \n]+) -->\n$")
      set(file "${CMAKE_MATCH_1}")
    endif()
  endif()
  # Body: from the line after the opening fence to the newline before the closing one.
  string(SUBSTRING "${rest}" ${open_at} -1 rest)
  string(FIND "${rest}" "\n" eol)
  math(EXPR body_at "${eol} + 1")
  string(SUBSTRING "${rest}" ${body_at} -1 rest)
  string(FIND "${rest}" "\n${fence}" close_at)
  if(close_at EQUAL -1)
    string(APPEND errors "  block ${count}: no closing fence\n")
    break()
  endif()
  string(SUBSTRING "${rest}" 0 ${close_at} body)
  math(EXPR after "${close_at} + 4")
  string(SUBSTRING "${rest}" ${after} -1 rest)
  string(REGEX MATCH "^[^\n]*" first_line "${body}")

  if(file STREQUAL "")
    string(APPEND errors "  block ${count} ('${first_line}'): no '<!-- snippet: examples/FILE -->' line right above it\n")
    continue()
  endif()
  if(NOT file MATCHES "^examples/" OR NOT EXISTS "${SOURCE_DIR}/${file}")
    string(APPEND errors "  block ${count}: '${file}' is not a file in examples/\n")
    continue()
  endif()
  get_filename_component(name "${file}" NAME)
  string(FIND "${examples_cmake}" "${name}" built)
  if(NOT file MATCHES "^examples/consumer/" AND built EQUAL -1)
    string(APPEND errors "  block ${count}: ${file} is not built and run by examples/CMakeLists.txt\n")
    continue()
  endif()
  file(READ "${SOURCE_DIR}/${file}" source)
  string(FIND "${source}" "${body}" found)
  if(found EQUAL -1)
    string(APPEND errors "  block ${count} ('${first_line}'): not found verbatim in ${file}\n")
  endif()
endwhile()

if(count EQUAL 0)
  string(APPEND errors "  no code blocks at all\n")
endif()
if(NOT errors STREQUAL "")
  message(FATAL_ERROR "docs/API.md snippets out of date:\n${errors}")
endif()
message(STATUS "docs/API.md: ${count} code blocks, each a verbatim excerpt of a built and tested example")
