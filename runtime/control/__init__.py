"""The simulated controller: runs the segments cycle by cycle (IK, blends, self-motion)."""
