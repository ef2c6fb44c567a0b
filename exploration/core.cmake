# The ROS-free core library of exploration: plain CMake, include()d by the catkin CMakeLists.txt of the
# package (and by standalone test builds). Defines the target `exploration_core`; the including
# CMakeLists must provide `laser_features_core` first (include laser_features/core.cmake).

include_guard(GLOBAL)
set(EXPLORATION_CORE_DIR ${CMAKE_CURRENT_LIST_DIR})

find_package(Eigen3 REQUIRED)  # header-only

add_library(exploration_core
  ${EXPLORATION_CORE_DIR}/src/motion_controller.cpp
  ${EXPLORATION_CORE_DIR}/src/occupancy_grid.cpp
  ${EXPLORATION_CORE_DIR}/src/frontier_explorer.cpp
  ${EXPLORATION_CORE_DIR}/src/grid_planner.cpp
  ${EXPLORATION_CORE_DIR}/src/frontier_goal.cpp
  ${EXPLORATION_CORE_DIR}/src/room_explorer.cpp
  ${EXPLORATION_CORE_DIR}/src/hallway_view.cpp
  ${EXPLORATION_CORE_DIR}/src/oblique_hallways.cpp
  ${EXPLORATION_CORE_DIR}/src/hallway_follower.cpp
  ${EXPLORATION_CORE_DIR}/src/topo_route.cpp
  ${EXPLORATION_CORE_DIR}/src/route_policy.cpp
  ${EXPLORATION_CORE_DIR}/src/progress_watch.cpp
  ${EXPLORATION_CORE_DIR}/src/hallway_doors.cpp
  ${EXPLORATION_CORE_DIR}/src/door_entry.cpp
  ${EXPLORATION_CORE_DIR}/src/hallway_door_stops.cpp
  ${EXPLORATION_CORE_DIR}/src/hallway_navigator.cpp
  ${EXPLORATION_CORE_DIR}/src/path_driver.cpp
  ${EXPLORATION_CORE_DIR}/src/waypoint_follower.cpp
  ${EXPLORATION_CORE_DIR}/src/room_visit.cpp
  ${EXPLORATION_CORE_DIR}/src/suite_visit.cpp
  ${EXPLORATION_CORE_DIR}/src/room_sequence.cpp
  ${EXPLORATION_CORE_DIR}/src/mission_runner.cpp
  ${EXPLORATION_CORE_DIR}/src/coordinator_params.cpp
  ${EXPLORATION_CORE_DIR}/src/coordinator.cpp
  ${EXPLORATION_CORE_DIR}/src/passive_places.cpp
  ${EXPLORATION_CORE_DIR}/src/door_crossings.cpp
  ${EXPLORATION_CORE_DIR}/src/run_summary.cpp
)
target_include_directories(exploration_core PUBLIC
  $<BUILD_INTERFACE:${EXPLORATION_CORE_DIR}/include>
)
target_link_libraries(exploration_core PUBLIC laser_features_core)
if(TARGET Eigen3::Eigen)
  target_link_libraries(exploration_core PUBLIC Eigen3::Eigen)
else()
  target_include_directories(exploration_core SYSTEM PUBLIC ${EIGEN3_INCLUDE_DIR})
endif()
target_compile_features(exploration_core PUBLIC cxx_std_17)
set_target_properties(exploration_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
