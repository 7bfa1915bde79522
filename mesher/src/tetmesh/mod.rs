//! The tetrahedral mesh data structure (flat arrays, typed ids, ghost vertex).
