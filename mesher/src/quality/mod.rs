//! Element quality (paper §6.1, §8): the one metric code path of the project.
