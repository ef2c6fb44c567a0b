# The ROS-free core library of pomdp_topo: plain CMake, include()d by the catkin CMakeLists.txt of the
# package (and by standalone test builds). Defines the target `pomdp_topo_core`; the including
# CMakeLists must provide `laser_features_core` first (include laser_features/core.cmake).

set(POMDP_TOPO_CORE_DIR ${CMAKE_CURRENT_LIST_DIR})

find_package(Eigen3 REQUIRED)  # header-only

add_library(pomdp_topo_core
  ${POMDP_TOPO_CORE_DIR}/src/topological_map.cpp
  ${POMDP_TOPO_CORE_DIR}/src/heading_estimator.cpp
  ${POMDP_TOPO_CORE_DIR}/src/map_io.cpp
  ${POMDP_TOPO_CORE_DIR}/src/graph_states.cpp
  ${POMDP_TOPO_CORE_DIR}/src/observation_model.cpp
  ${POMDP_TOPO_CORE_DIR}/src/pomdp_localizer.cpp
  ${POMDP_TOPO_CORE_DIR}/src/front_end.cpp
  ${POMDP_TOPO_CORE_DIR}/src/dead_reckoning_gate.cpp
  ${POMDP_TOPO_CORE_DIR}/src/loop_hypotheses.cpp
  ${POMDP_TOPO_CORE_DIR}/src/map_builder.cpp
  ${POMDP_TOPO_CORE_DIR}/src/map_builder_frontier.cpp
  ${POMDP_TOPO_CORE_DIR}/src/map_builder_localized.cpp
  ${POMDP_TOPO_CORE_DIR}/src/map_builder_loop_check.cpp
  ${POMDP_TOPO_CORE_DIR}/src/map_updater.cpp
  ${POMDP_TOPO_CORE_DIR}/src/params_check.cpp
)
target_include_directories(pomdp_topo_core PUBLIC
  $<BUILD_INTERFACE:${POMDP_TOPO_CORE_DIR}/include>
)
target_link_libraries(pomdp_topo_core PUBLIC laser_features_core)
if(TARGET Eigen3::Eigen)
  target_link_libraries(pomdp_topo_core PUBLIC Eigen3::Eigen)
else()
  target_include_directories(pomdp_topo_core SYSTEM PUBLIC ${EIGEN3_INCLUDE_DIR})
endif()
target_compile_features(pomdp_topo_core PUBLIC cxx_std_17)
set_target_properties(pomdp_topo_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
