//! logo-algo (work in progress).
