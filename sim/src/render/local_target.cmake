# Sets VID_SIM_RENDER_TARGET to the library that holds the render sources: vid_sim when the
# simulator library exists, else a local library built from the same sources (so render
# tests and benchmarks build on their own).
include(${CMAKE_CURRENT_LIST_DIR}/sources.cmake)
if(TARGET vid_sim)
  set(VID_SIM_RENDER_TARGET vid_sim)
else()
  if(NOT TARGET vid_sim_render_local)
    add_library(vid_sim_render_local STATIC ${VID_SIM_RENDER_SOURCES})
    target_compile_options(vid_sim_render_local PRIVATE ${VID_WARNINGS})
    target_include_directories(vid_sim_render_local PUBLIC ${VID_SIM_RENDER_INCLUDE_DIRS})
    target_link_libraries(vid_sim_render_local PUBLIC ${VID_SIM_RENDER_LIBS} Eigen3::Eigen)
  endif()
  set(VID_SIM_RENDER_TARGET vid_sim_render_local)
endif()
