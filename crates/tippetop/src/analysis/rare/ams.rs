//! Adaptive multilevel splitting (see the module [`super`]).
