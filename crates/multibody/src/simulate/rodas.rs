//! Rodas4: an L-stable Rosenbrock method for stiff mechanisms (to be written).
