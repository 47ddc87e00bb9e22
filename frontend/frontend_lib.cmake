# KLT frontend (OpenCV). Included from frontend/CMakeLists.txt.
vid_add_library(vid_frontend
  SOURCES src/grid_detector.cpp src/gyro_integrator.cpp src/outlier_rejection.cpp
          src/stereo_matcher.cpp src/patch_refiner.cpp src/klt_tracker.cpp src/track_drawing.cpp
          src/image_decode.cpp
  PUBLIC_LIBS vid_camera opencv_core opencv_imgproc opencv_video
  PRIVATE_LIBS opencv_features2d opencv_calib3d opencv_imgcodecs)

# FrontendParams from YAML (uses io's strict YAML reader).
if(TARGET vid_io)
  vid_add_library(vid_frontend_config
    SOURCES src/frontend_params_yaml.cpp
    PUBLIC_LIBS vid_frontend vid_io)
endif()
