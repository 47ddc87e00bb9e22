# Data-driven mass identification (ELM, RELM, OSELM; seed section 4.2.5), added to
# vid_massid_core by dynamics/massid/CMakeLists.txt.
set(MASSID_ELM_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/elm.cpp
  ${CMAKE_CURRENT_LIST_DIR}/oselm.cpp
  ${CMAKE_CURRENT_LIST_DIR}/features.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mass_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/study.cpp
  ${CMAKE_CURRENT_LIST_DIR}/study_tables.cpp)
