//! The paper's Euler-angle model (App. A). (work in progress)
