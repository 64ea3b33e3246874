//! parry3d baseline (stub until written).
