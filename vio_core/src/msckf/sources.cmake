# Visual MSCKF update sources, compiled into the vio_core library (included by
# vio_core/CMakeLists.txt). Absolute paths.
set(VIO_MSCKF_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/projection.cpp
  ${CMAKE_CURRENT_LIST_DIR}/triangulation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/linear_algebra.cpp
  ${CMAKE_CURRENT_LIST_DIR}/innovation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/feature_database.cpp
  ${CMAKE_CURRENT_LIST_DIR}/visual_update.cpp
)
