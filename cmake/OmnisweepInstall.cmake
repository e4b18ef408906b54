# `cmake --install build [--prefix P]`: the client SDK (static libraries, public headers, the
# generated DDS types), a CMake package (find_package(omnisweep) -> omnisweep::client_sdk), a
# pkg-config file (omnisweep.pc), the omnisweep-* programs and the QoS profiles.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# In link order: each library before those it uses.
set(OMNISWEEP_SDK_MODULES record ros2 client dds wire codec reproject gpu shaders dataset image_io rig image camera msgs ros2_msgs)
set(sdk_targets omnisweep_client_sdk)
set(OMNISWEEP_PC_LIBS "")
foreach(module ${OMNISWEEP_SDK_MODULES})
  list(APPEND sdk_targets omnisweep_${module})
  set_target_properties(omnisweep_${module} PROPERTIES EXPORT_NAME ${module})
  get_target_property(type omnisweep_${module} TYPE)
  if(NOT type STREQUAL "INTERFACE_LIBRARY")
    string(APPEND OMNISWEEP_PC_LIBS " -lomnisweep_${module}")
  endif()
endforeach()
set_target_properties(omnisweep_client_sdk PROPERTIES EXPORT_NAME client_sdk)
target_include_directories(omnisweep_msgs PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/omnisweep/generated>)
target_include_directories(omnisweep_ros2_msgs PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/omnisweep/generated>)

install(TARGETS ${sdk_targets} EXPORT omnisweepTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/client_sdk/include/omnisweep DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_BINARY_DIR}/idl/generated/omnisweep_msgs.h
              ${PROJECT_BINARY_DIR}/idl/generated/omnisweep_msgsPubSubTypes.h
              ${PROJECT_BINARY_DIR}/idl/generated/ros2_msgs.h
              ${PROJECT_BINARY_DIR}/idl/generated/ros2_msgsPubSubTypes.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/omnisweep/generated)
install(FILES ${PROJECT_BINARY_DIR}/shaders/generated/include/omnisweep/gpu/shader_ids.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/omnisweep/gpu)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/qos/omnisweep_qos.xml DESTINATION ${CMAKE_INSTALL_DATADIR}/omnisweep/qos)

set(cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/omnisweep)
install(EXPORT omnisweepTargets NAMESPACE omnisweep:: DESTINATION ${cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/omnisweepConfig.cmake.in
  ${PROJECT_BINARY_DIR}/omnisweepConfig.cmake INSTALL_DESTINATION ${cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/omnisweepConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/omnisweepConfig.cmake ${PROJECT_BINARY_DIR}/omnisweepConfigVersion.cmake
  DESTINATION ${cmake_dir})

# pkg-config: the prefix is fixed when installing (cmake --install --prefix P rewrites it).
configure_file(${PROJECT_SOURCE_DIR}/cmake/omnisweep.pc.in ${PROJECT_BINARY_DIR}/omnisweep.pc.configured @ONLY)
install(CODE "
  file(READ \"${PROJECT_BINARY_DIR}/omnisweep.pc.configured\" pc)
  string(REPLACE \"${CMAKE_INSTALL_PREFIX}\" \"\${CMAKE_INSTALL_PREFIX}\" pc \"\${pc}\")
  file(WRITE \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig/omnisweep.pc\" \"\${pc}\")
  message(STATUS \"Installing: \$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig/omnisweep.pc\")")
