//! Not a library: a workspace member whose dependencies align the features of dependencies
//! the other members share, so that `scripts/test`'s builds with and without the `mpi`
//! features reuse each other's builds (see its `Cargo.toml`). It has no code and is never
//! published.
