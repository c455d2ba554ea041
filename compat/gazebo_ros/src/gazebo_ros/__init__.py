"""bullet_sim's stand-in for gazebo_ros's Python package: gazebo_interface."""
