# What `cmake --install build --prefix P` puts where (docs/install.md), the CMake package
# `find_package(TigrisTLM)` and the Debian package of `cpack -G DEB`. Everything the binary and
# the Python module read is found relative to them (PREFIX/share/tigris), so a prefix works
# wherever it is copied.
include(CMakePackageConfigHelpers)

# The libraries as TigrisTLM::<name> (tigris_sw_ref -> TigrisTLM::sw_ref). They are static: a
# program that links them needs no Tigris at run time.
set(TIGRIS_EXPORTED_LIBRARIES
    tigris_core tigris_config tigris_cloud tigris_sw_ref tigris_io tigris_workloads tigris_traces
    tigris_workload_trace tigris_registration tigris_vcd tigris_tlm tigris_hw_policies tigris_hw tigris_testbench)
if(TIGRIS_RTL)
  list(APPEND TIGRIS_EXPORTED_LIBRARIES tigris_rtl)
endif()
# The PCL search back-end with the model in the loop: the plug-in (registration/search_plugin.hpp)
# and the model server a program hands its jobs to (testbench/accel_in_loop.hpp).
add_library(tigris_pcl_search INTERFACE)
target_link_libraries(tigris_pcl_search INTERFACE tigris_registration tigris_testbench)
foreach(lib ${TIGRIS_EXPORTED_LIBRARIES} tigris_pcl_search)
  string(REGEX REPLACE "^tigris_" "" short ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS tigris RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${TIGRIS_EXPORTED_LIBRARIES} tigris_pcl_search EXPORT TigrisTLMTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}/tigris)
foreach(dir core config sw_ref traces workloads registration tlm hw testbench)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tigris/${dir}
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/presets/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tigris/presets)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples
        PATTERN "build" EXCLUDE PATTERN "__pycache__" EXCLUDE)

set(TIGRIS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/TigrisTLM)
install(EXPORT TigrisTLMTargets NAMESPACE TigrisTLM:: DESTINATION ${TIGRIS_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/TigrisTLMConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/TigrisTLMConfig.cmake INSTALL_DESTINATION ${TIGRIS_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/TigrisTLMConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/TigrisTLMConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/TigrisTLMConfigVersion.cmake
        DESTINATION ${TIGRIS_CMAKE_DIR})

# `cpack -G DEB` in the build folder: tigris-tlm_<version>_<arch>.deb, installed under /usr with
# `apt-get install ./tigris-tlm_*.deb`. Its dependencies are the Debian packages a user of the
# binary, the Python tools and the CMake package needs (the -dev ones for the headers).
set(CPACK_PACKAGE_NAME tigris-tlm)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "Tigris TLM developers <tigris-tlm@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "SystemC/TLM model of the Tigris KD-tree search accelerator, its golden model and PCL back-end")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libsystemc-dev, libpcl-dev, libeigen3-dev, nlohmann-json3-dev, libcli11-dev, libzstd-dev, libssl-dev, \
python3, python3-numpy, python3-matplotlib, cmake, g++")
include(CPack)
