//! Reading and writing what crosses the program's edge: percept-stream records and, later, raw
//! sensor logs and trajectories. Readers here take strings or bytes and do no I/O of their own;
//! the command line owns the files.

pub mod record;
