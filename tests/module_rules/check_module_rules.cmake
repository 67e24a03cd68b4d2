# The module rules of ARCHITECTURE.md, checked on the build's link graph and on the sources.
#   cmake -DGRAPH=<link_graph.txt> -DSOURCE_DIR=<repo> [-DEXPECT=<rule;rule> -DEXPECT_COUNT=<n>]
#         -P check_module_rules.cmake
# GRAPH is written at configure time by write_link_graph.cmake (every target, its direct deps);
# dependencies are followed transitively here. Sources are globbed at run time, so new files and
# new targets are checked without touching this script. Without EXPECT the check fails on any
# breach; with EXPECT (the self-test on fixtures/) it fails unless exactly those rules are broken
# (and, with EXPECT_COUNT, by exactly that many breaches).
#
# Rules (id: what breaks it):
#   headless-graphics  a headless library (base, config, mesh, cut, ipc, physics, firmware_host)
#                      links EGL / GLES / GL / GBM / DRM / X11 / GLM, directly or through others
#   rt-core-openmesh   a file under rt_core/ includes OpenMesh, or an rt_core library links it
#   firmware-host-ipc  a file under firmware_host/ includes rt_core/, or its targets link kerf_ipc
#   display-rt-core    a display/ target links an rt_core/ target other than kerf_ipc, or a
#                      display/ file includes rt_core/ outside rt_core/ipc/
#   physics-io         a file under rt_core/physics/ includes <fstream> <cstdio> <stdio.h>
#                      <iostream> <fcntl.h> <unistd.h> or spdlog, or calls open/fopen/printf/
#                      fprintf/puts/std::cout/cerr/clog; or kerf_physics links spdlog or TOML
#   config-link        a library that reads no configuration links kerf_config, or any target
#                      but kerf_config links toml++ itself
cmake_minimum_required(VERSION 3.25)
foreach(var GRAPH SOURCE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_module_rules: -D${var}=... is required")
  endif()
endforeach()

get_filename_component(SOURCE_DIR "${SOURCE_DIR}" ABSOLUTE)
set(broken_rules "")
set(report "")
macro(breach rule text)
  list(APPEND broken_rules ${rule})
  string(APPEND report "  [${rule}] ${text}\n")
endmacro()

# ---- the link graph --------------------------------------------------------------------------
file(STRINGS "${GRAPH}" lines)
set(all_targets "")
foreach(line IN LISTS lines)
  string(REPLACE "|" ";" fields "${line}")
  list(GET fields 0 name)
  list(GET fields 1 type)
  list(GET fields 2 dir)
  list(LENGTH fields n)
  set(deps "")
  if(n GREATER 3)
    list(SUBLIST fields 3 -1 deps)
  endif()
  string(MAKE_C_IDENTIFIER "${name}" key)
  set(DIR_${key} "${dir}")
  set(TYPE_${key} "${type}")
  set(DEPS_${key} "${deps}")
  list(APPEND all_targets "${name}")
endforeach()

# closure(<target> <out>): every target and library <target> links, transitively.
function(closure target out)
  set(result "")
  set(queue "${target}")
  while(queue)
    list(POP_FRONT queue t)
    string(MAKE_C_IDENTIFIER "${t}" key)
    foreach(d IN LISTS DEPS_${key})
      if(NOT d IN_LIST result)
        list(APPEND result "${d}")
        list(APPEND queue "${d}")
      endif()
    endforeach()
  endwhile()
  set(${out} "${result}" PARENT_SCOPE)
endfunction()

function(targets_under prefix out)
  set(result "")
  foreach(t IN LISTS all_targets)
    string(MAKE_C_IDENTIFIER "${t}" key)
    if(DIR_${key} MATCHES "^${prefix}(/|$)")
      list(APPEND result "${t}")
    endif()
  endforeach()
  set(${out} "${result}" PARENT_SCOPE)
endfunction()

set(graphics_regex "egl|gles|opengl|gbm|glm|(^|::)gl$|^gl$|x11|drm")
set(headless kerf_base kerf_config kerf_mesh kerf_cut kerf_ipc kerf_physics kerf_firmware_host)
foreach(t IN LISTS headless)
  if(NOT t IN_LIST all_targets)
    continue()
  endif()
  closure(${t} deps)
  foreach(d IN LISTS deps)
    string(TOLOWER "${d}" lower)
    if(lower MATCHES "${graphics_regex}")
      breach(headless-graphics "${t} links ${d}")
    endif()
  endforeach()
endforeach()

targets_under(rt_core rt_targets)
foreach(t IN LISTS rt_targets)
  # Libraries only: the kerf-rt executable may load the scene through kerf_mesh's plain-array API
  # at start-up (no OpenMesh header in rt_core/, which the source grep below checks).
  string(MAKE_C_IDENTIFIER "${t}" key)
  if(TYPE_${key} STREQUAL "EXECUTABLE")
    continue()
  endif()
  closure(${t} deps)
  foreach(d IN LISTS deps)
    if(d MATCHES "OpenMesh")
      breach(rt-core-openmesh "${t} links ${d}")
    endif()
  endforeach()
endforeach()

targets_under(firmware_host fw_targets)
foreach(t IN LISTS fw_targets)
  closure(${t} deps)
  if(kerf_ipc IN_LIST deps)
    breach(firmware-host-ipc "${t} links kerf_ipc")
  endif()
endforeach()

targets_under(display display_targets)
foreach(t IN LISTS display_targets)
  closure(${t} deps)
  foreach(d IN LISTS deps)
    string(MAKE_C_IDENTIFIER "${d}" key)
    if(DEFINED DIR_${key} AND DIR_${key} MATCHES "^rt_core(/|$)" AND NOT d STREQUAL "kerf_ipc")
      breach(display-rt-core "${t} links ${d} (${DIR_${key}}); display may link only kerf_ipc")
    endif()
  endforeach()
endforeach()

if(kerf_physics IN_LIST all_targets)
  closure(kerf_physics deps)
  foreach(d IN LISTS deps)
    if(d MATCHES "spdlog|tomlplusplus|^kerf_config$")
      breach(physics-io "kerf_physics links ${d}")
    endif()
  endforeach()
endif()

set(no_config kerf_base kerf_mesh kerf_cut kerf_ipc kerf_physics kerf_firmware_host
              kerf_hapsim_core kerf_render kerf_egl)
foreach(t IN LISTS no_config)
  if(t IN_LIST all_targets)
    closure(${t} deps)
    if(kerf_config IN_LIST deps)
      breach(config-link "${t} links kerf_config but reads no configuration")
    endif()
  endif()
endforeach()
foreach(t IN LISTS all_targets)
  string(MAKE_C_IDENTIFIER "${t}" key)
  if(NOT t STREQUAL "kerf_config" AND DEPS_${key} MATCHES "tomlplusplus")
    breach(config-link "${t} links toml++ itself (only kerf_config parses TOML)")
  endif()
endforeach()

# ---- the sources -----------------------------------------------------------------------------
# grep(<rule> <folder> <regex> <what>): every line of every C++ file under <folder> matching
# <regex>, after dropping // comments, is a breach.
function(grep rule folder regex what)
  file(GLOB_RECURSE files LIST_DIRECTORIES false "${SOURCE_DIR}/${folder}/*.cpp"
       "${SOURCE_DIR}/${folder}/*.hpp" "${SOURCE_DIR}/${folder}/*.h" "${SOURCE_DIR}/${folder}/*.cc")
  foreach(f IN LISTS files)
    file(STRINGS "${f}" hits REGEX "${regex}")
    foreach(hit IN LISTS hits)
      string(REGEX REPLACE "//.*$" "" code "${hit}")
      if(code MATCHES "${regex}")
        file(RELATIVE_PATH rel "${SOURCE_DIR}" "${f}")
        string(STRIP "${code}" code)
        set(broken_rules ${broken_rules} ${rule} PARENT_SCOPE)
        set(report "${report}  [${rule}] ${rel}: ${what}: ${code}\n")
      endif()
    endforeach()
  endforeach()
  set(report "${report}" PARENT_SCOPE)
endfunction()

set(inc "^[ \t]*#[ \t]*include[ \t]*[<\"]")
grep(rt-core-openmesh rt_core "${inc}OpenMesh" "includes OpenMesh")
grep(firmware-host-ipc firmware_host "${inc}rt_core/" "includes rt_core")
grep(display-rt-core display "${inc}rt_core/([^i]|i[^p]|ip[^c]|ipc[^/])" "includes rt_core beyond ipc")
grep(physics-io rt_core/physics
     "${inc}(fstream|cstdio|stdio\\.h|iostream|fcntl\\.h|unistd\\.h|spdlog)" "includes an I/O header")
grep(physics-io rt_core/physics
     "(^|[^A-Za-z0-9_.>])(f?open|printf|fprintf|puts|perror)[ \t]*\\(|std::(cout|cerr|clog)|spdlog::"
     "does I/O")

# ---- verdict ---------------------------------------------------------------------------------
list(LENGTH broken_rules breach_count)
list(REMOVE_DUPLICATES broken_rules)
list(SORT broken_rules)
if(DEFINED EXPECT)
  set(expected ${EXPECT})
  list(SORT expected)
  if(NOT broken_rules STREQUAL expected OR (DEFINED EXPECT_COUNT AND
                                             NOT breach_count EQUAL EXPECT_COUNT))
    message(FATAL_ERROR "module rules self-test: expected ${EXPECT_COUNT} breaches of "
                        "[${expected}], got ${breach_count} of [${broken_rules}]:\n${report}")
  endif()
  message(STATUS "module rules self-test: every planted breach found:\n${report}")
elseif(broken_rules)
  message(FATAL_ERROR "module rules broken (see ARCHITECTURE.md; tests/module_rules/):\n${report}")
else()
  list(LENGTH all_targets n)
  message(STATUS "module rules hold (${n} targets in the link graph)")
endif()
