//! Traffic generation: lanes, arrivals, classes, weights and axle layouts.
