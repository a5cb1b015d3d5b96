# The point-cloud readers (the tigris_io library, workloads/CMakeLists.txt), listed once: the fuzz build
# (fuzz/CMakeLists.txt) compiles the same files with its instrumentation.
set(TIGRIS_IO_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/reader_util.cpp
  ${CMAKE_CURRENT_LIST_DIR}/kitti_bin.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/pcd_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/lzf.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cloud_io.cpp
)
