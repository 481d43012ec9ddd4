//! DAQ nodes: clocks (offset, drift, jitter, resynchronisation) and labelled faults.
