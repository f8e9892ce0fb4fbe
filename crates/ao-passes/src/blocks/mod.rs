//! Shared AO building blocks (subgraphs any technique composes).
