"""vid-bag2asl: stream ROS1/ROS2 bags into the VID-MSCKF dataset folder format (docs/formats.md §1)."""
