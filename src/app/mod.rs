//! The application layer: drives runs. A resolved scenario goes through the time loop
//! (`sim`) into an output (`output`, or any other `Recorder`); sweeps run many.

pub mod estimate;
pub mod pipeline;
pub mod run;
pub mod space;
pub mod sweep;
