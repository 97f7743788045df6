"""The arm: its chain, forward kinematics, Jacobians and Hessians, and its collision capsules (pure core)."""
