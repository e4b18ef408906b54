# Small helpers in the spirit of COLMAP_ADD_LIBRARY / COLMAP_ADD_TEST: a module is one
# library, its tests sit beside its sources, and programs are named omnisweep-*.

set(OMNISWEEP_WARNINGS -Wall -Wextra -Wpedantic -Wno-deprecated-copy)

# omnisweep_add_library(NAME SRCS a.cc b.cc [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Declares omnisweep_NAME with the alias omnisweep::NAME. Without SRCS it is header-only.
function(omnisweep_add_library NAME)
  cmake_parse_arguments(ARG "" "" "SRCS;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target omnisweep_${NAME})
  if(ARG_SRCS)
    add_library(${target} STATIC ${ARG_SRCS})
    target_compile_options(${target} PRIVATE ${OMNISWEEP_WARNINGS})
    target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    target_include_directories(${target} PUBLIC
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/client_sdk/include>
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
      $<INSTALL_INTERFACE:include>)
  else()
    add_library(${target} INTERFACE)
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS})
    target_include_directories(${target} INTERFACE
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/client_sdk/include>
      $<INSTALL_INTERFACE:include>)
  endif()
  add_library(omnisweep::${NAME} ALIAS ${target})
endfunction()

# omnisweep_discover_tests(TARGET [PREFIX p] [LABELS ...] [TIMEOUT seconds] [ENVIRONMENT ...]
#                          [PROPERTIES name value ...])
# Each TEST of the GoogleTest binary TARGET becomes one ctest entry named PREFIX + Suite.Test, in
# its own process with its own TIMEOUT (120 s unless given), so one slow test on a slow machine
# cannot take the others' time. The environment always holds OMNISWEEP_SHARED_DIR and
# OMNISWEEP_BIN_DIR. A binary may be discovered more than once under different prefixes.
function(omnisweep_discover_tests TARGET)
  cmake_parse_arguments(ARG "" "PREFIX;TIMEOUT" "LABELS;ENVIRONMENT;PROPERTIES" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  string(MAKE_C_IDENTIFIER "${TARGET}_${ARG_PREFIX}" id)
  gtest_discover_tests(${TARGET} TEST_PREFIX "${ARG_PREFIX}" TEST_LIST ${id}_TESTS DISCOVERY_TIMEOUT 60)
  # Properties go on in a file ctest includes after the discovered tests: gtest_discover_tests'
  # own PROPERTIES splits list values (several labels, several environment variables).
  list(JOIN ARG_LABELS ";" labels)
  list(APPEND ARG_ENVIRONMENT "OMNISWEEP_SHARED_DIR=${OMNISWEEP_SHARED_DIR}"
    "OMNISWEEP_BIN_DIR=${PROJECT_BINARY_DIR}/bin")
  list(JOIN ARG_ENVIRONMENT ";" environment)
  set(props "LABELS \"${labels}\" TIMEOUT ${ARG_TIMEOUT} ENVIRONMENT \"${environment}\"")
  while(ARG_PROPERTIES)
    list(POP_FRONT ARG_PROPERTIES key value)
    string(APPEND props " ${key} \"${value}\"")
  endwhile()
  set(file ${CMAKE_CURRENT_BINARY_DIR}/${id}_properties.cmake)
  file(WRITE ${file} "foreach(t IN LISTS ${id}_TESTS)\n  set_tests_properties(\"\${t}\" PROPERTIES ${props})\nendforeach()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${file})
endfunction()

# omnisweep_add_test(NAME SRCS a_test.cc [DEPS ...] [LABELS ...] [TIMEOUT seconds]
#                    [PROPERTIES name value ...] [HIDDEN_MEMORY])
# One GoogleTest binary, build/tests/omnisweep_NAME_test; each TEST becomes one ctest entry
# labelled NAME and LABELS, with the extra PROPERTIES (omnisweep_discover_tests).
# HIDDEN_MEMORY (the GPU suites): each TEST runs again as hidden_memory/Suite.Test (labels vulkan,
# memory) with every memory property a discrete GPU may lack hidden from the device
# (OMNISWEEP_VK_HIDE_MEMORY=all: no device-local + host-visible memory, no cached, no coherent
# host memory), so lavapipe runs the staging, uncached-readback and flush/invalidate paths too.
# One entry per test, each with its own limit: the depth binary as one process took 229 s under
# the sanitizers here and ran past its 300 s on a slower CI machine.
function(omnisweep_add_test NAME)
  if(NOT OMNISWEEP_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "HIDDEN_MEMORY" "TIMEOUT" "SRCS;DEPS;LABELS;PROPERTIES" ${ARGN})
  set(target omnisweep_${NAME}_test)
  add_executable(${target} ${ARG_SRCS})
  set_target_properties(${target} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  target_compile_options(${target} PRIVATE ${OMNISWEEP_WARNINGS})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} omnisweep_test_support GTest::gtest GTest::gtest_main)
  omnisweep_discover_tests(${target} LABELS ${NAME} ${ARG_LABELS} TIMEOUT "${ARG_TIMEOUT}"
    PROPERTIES ${ARG_PROPERTIES})
  if(ARG_HIDDEN_MEMORY)
    omnisweep_discover_tests(${target} PREFIX "hidden_memory/" LABELS vulkan memory TIMEOUT 300
      ENVIRONMENT OMNISWEEP_VK_HIDE_MEMORY=all)
  endif()
endfunction()

# omnisweep_add_executable(NAME SRCS main.cc [DEPS ...]) builds build/bin/omnisweep-NAME.
function(omnisweep_add_executable NAME)
  cmake_parse_arguments(ARG "" "" "SRCS;DEPS" ${ARGN})
  set(target omnisweep-${NAME})
  add_executable(${target} ${ARG_SRCS})
  target_compile_options(${target} PRIVATE ${OMNISWEEP_WARNINGS})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS})
  install(TARGETS ${target} RUNTIME DESTINATION bin)
endfunction()
