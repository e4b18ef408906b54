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

# omnisweep_add_test(NAME SRCS a_test.cc [DEPS ...] [LABELS ...] [TIMEOUT seconds]
#                    [PROPERTIES name value ...])
# One GoogleTest binary; each TEST becomes one ctest entry with the extra PROPERTIES.
function(omnisweep_add_test NAME)
  if(NOT OMNISWEEP_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "TIMEOUT" "SRCS;DEPS;LABELS;PROPERTIES" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  set(target omnisweep_${NAME}_test)
  add_executable(${target} ${ARG_SRCS})
  set_target_properties(${target} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  target_compile_options(${target} PRIVATE ${OMNISWEEP_WARNINGS})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} omnisweep_test_support GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60)
  # Properties go on in a file ctest includes after the discovered tests: gtest_discover_tests'
  # own PROPERTIES splits list values (several labels, several environment variables).
  set(props "LABELS \"${NAME};${ARG_LABELS}\" TIMEOUT ${ARG_TIMEOUT}")
  string(APPEND props " ENVIRONMENT \"OMNISWEEP_SHARED_DIR=${OMNISWEEP_SHARED_DIR};OMNISWEEP_BIN_DIR=${PROJECT_BINARY_DIR}/bin\"")
  while(ARG_PROPERTIES)
    list(POP_FRONT ARG_PROPERTIES key value)
    string(APPEND props " ${key} \"${value}\"")
  endwhile()
  set(file ${CMAKE_CURRENT_BINARY_DIR}/${target}_properties.cmake)
  file(WRITE ${file} "foreach(t IN LISTS ${target}_TESTS)\n  set_tests_properties(\"\${t}\" PROPERTIES ${props})\nendforeach()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${file})
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
