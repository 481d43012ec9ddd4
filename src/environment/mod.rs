//! Environment and condition: temperature and damage driving the bridge stiffness.
