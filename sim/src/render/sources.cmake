# Renderer / scene / feature-level simulation sources of the vid_sim library (render engineer).
# sim/CMakeLists.txt includes this file, adds ${VID_SIM_RENDER_SOURCES} to vid_sim and links
# ${VID_SIM_RENDER_LIBS}.
set(VID_SIM_RENDER_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/yaml_fields.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene_config.cpp
  ${CMAKE_CURRENT_LIST_DIR}/texture.cpp
  ${CMAKE_CURRENT_LIST_DIR}/scene.cpp
  ${CMAKE_CURRENT_LIST_DIR}/render_config.cpp
  ${CMAKE_CURRENT_LIST_DIR}/renderer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/feature_simulator.cpp
)
# vid_camera (frontend camera models), OpenCV core/imgproc, yaml-cpp; io/include for
# io/errors.h (header-only ConfigError).
set(VID_SIM_RENDER_LIBS vid_camera opencv_core opencv_imgproc yaml-cpp)
set(VID_SIM_RENDER_INCLUDE_DIRS ${CMAKE_CURRENT_LIST_DIR}/../../include
    ${CMAKE_CURRENT_LIST_DIR}/../../../io/include)
