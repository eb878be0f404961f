"""The robot model at run time: kinematics, dynamics, geometry, limits, joint names."""
