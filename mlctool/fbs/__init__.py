"""FATEK FBs NC positioning: the positioning-program language, its register tables, the axis model."""
