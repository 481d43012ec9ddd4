//! Weigh-in-motion station models: COST 323 accuracy classes and strip physics.
