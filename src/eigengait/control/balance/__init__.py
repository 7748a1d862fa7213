"""Balance control: quaternion PD, momentum Jacobian, virtual force/torque, tunable foot
compensation, tracking."""
