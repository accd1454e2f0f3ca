//! logo-data (work in progress).
