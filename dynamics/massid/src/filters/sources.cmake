# Model-based mass-identification methods (EKF, UKF, MSCKF, SWLS); included by
# dynamics/massid/CMakeLists.txt.
set(MASSID_FILTER_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/quadrotor_mass_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tuning.cpp
  ${CMAKE_CURRENT_LIST_DIR}/msckf.cpp
  ${CMAKE_CURRENT_LIST_DIR}/swls_residuals.cpp
  ${CMAKE_CURRENT_LIST_DIR}/swls.cpp
  ${CMAKE_CURRENT_LIST_DIR}/estimators.cpp)
