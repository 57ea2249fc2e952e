//! lplace: possibilistic place recognition.
