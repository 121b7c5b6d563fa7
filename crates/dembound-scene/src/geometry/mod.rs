//! Where bodies are and who is near whom: the box, the cell grid, the
//! Verlet lists and the ghost layer.

pub mod cells;
pub mod decomposition;
pub mod domain;
pub mod ghosts;
pub mod neighbour;
