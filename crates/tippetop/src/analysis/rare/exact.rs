//! Exact one-dimensional answers (see the module [`super`]).
