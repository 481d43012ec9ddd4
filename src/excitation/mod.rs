//! Ambient excitation: band-limited random loads on the bridge.
