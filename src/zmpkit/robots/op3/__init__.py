"""The virtual ROBOTIS OP3: Menagerie's MJCF from an optional wheel, a robot.yaml and a truth."""
