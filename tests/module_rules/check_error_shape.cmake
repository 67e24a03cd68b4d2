# The one error shape (config/base/error.hpp), checked on the sources so no other form comes back.
#   cmake -DSOURCE_DIR=<repo> [-DEXPECT_COUNT=<n>] -P check_error_shape.cmake
# Headers under config/ display/ firmware_host/ rt_core/ tools/ are read at run time. Breaches:
#   char-to-string  `const char* to_string(`: every to_string of an enum returns std::string_view
#   own-error       a `struct <Name>Error {` of its own (an error type is `using X = Error<Code>`
#                   or `struct X : Error<Code>`), or `using <Name>Error = ` anything but Error<...>
#   own-printer     an error struct printing itself another way: `std::string to_string() const`
#                   or `std::string message() const` declared outside config/base/error.hpp
# PENDING names the files not migrated yet, exactly: a listed file that no longer breaks the rule
# fails the check too, so the list only shrinks. Without EXPECT_COUNT any breach outside PENDING
# fails; with it (the self-test on fixtures/error_tree) exactly that many breaches must be found.
cmake_minimum_required(VERSION 3.25)
if(NOT DEFINED SOURCE_DIR)
  message(FATAL_ERROR "check_error_shape: -DSOURCE_DIR=... is required")
endif()
get_filename_component(SOURCE_DIR "${SOURCE_DIR}" ABSOLUTE)

# Not yet migrated to kerf::Error (issue 8 item 3); each entry is "<rule>:<path>".
set(PENDING "")
if(NOT DEFINED EXPECT_COUNT)
  set(PENDING)
endif()

file(GLOB_RECURSE headers RELATIVE "${SOURCE_DIR}"
     "${SOURCE_DIR}/config/*.hpp" "${SOURCE_DIR}/display/*.hpp" "${SOURCE_DIR}/firmware_host/*.hpp"
     "${SOURCE_DIR}/rt_core/*.hpp" "${SOURCE_DIR}/tools/*.hpp")
set(found "")
set(report "")
foreach(h IN LISTS headers)
  if(h STREQUAL "config/base/error.hpp")
    continue()
  endif()
  # One list element per line: `;` and brackets (which CMake lists treat specially) masked first.
  file(READ "${SOURCE_DIR}/${h}" text)
  string(REPLACE ";" "<sc>" text "${text}")
  string(REPLACE "[" "<lb>" text "${text}")
  string(REPLACE "]" "<rb>" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(hits "")
  foreach(line IN LISTS lines)
    if(line MATCHES "^[ \t]*(inline[ \t]+)?(constexpr[ \t]+)?const char\\*[ \t]+to_string\\(")
      list(APPEND hits char-to-string)
    endif()
    if(line MATCHES "^[ \t]*struct[ \t]+[A-Za-z0-9_]*Error[ \t]*{")
      list(APPEND hits own-error)
    endif()
    if(line MATCHES "^[ \t]*using[ \t]+[A-Za-z0-9_]*Error[ \t]*=" AND NOT line MATCHES "=[ \t]*(kerf::)?Error<")
      list(APPEND hits own-error)
    endif()
    if(line MATCHES "std::string[ \t]+(to_string|message)\\(\\)[ \t]*const")
      list(APPEND hits own-printer)
    endif()
  endforeach()
  list(REMOVE_DUPLICATES hits)
  foreach(rule IN LISTS hits)
    list(APPEND found "${rule}:${h}")
  endforeach()
endforeach()

set(breaches 0)
foreach(f IN LISTS found)
  if(NOT f IN_LIST PENDING)
    math(EXPR breaches "${breaches} + 1")
    string(APPEND report "  [${f}]\n")
  endif()
endforeach()
foreach(p IN LISTS PENDING)
  if(NOT p IN_LIST found)
    math(EXPR breaches "${breaches} + 1")
    string(APPEND report "  [${p}] is listed as pending but is migrated: remove it from PENDING\n")
  endif()
endforeach()

if(DEFINED EXPECT_COUNT)
  if(NOT breaches EQUAL EXPECT_COUNT)
    message(FATAL_ERROR "check_error_shape self-test: expected ${EXPECT_COUNT} breaches, "
                        "found ${breaches}:\n${report}")
  endif()
  message(STATUS "check_error_shape self-test: all ${breaches} planted breaches found")
elseif(breaches GREATER 0)
  message(FATAL_ERROR "error shape (config/base/error.hpp) broken ${breaches} time(s):\n${report}"
                      "Use kerf::Error<Code> with to_string(Code) -> std::string_view and print "
                      "with message().")
else()
  list(LENGTH PENDING pending_count)
  message(STATUS "error shape: no breach (${pending_count} pending entries, listed in the script)")
endif()
