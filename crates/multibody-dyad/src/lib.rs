//! Reads Dyad model files into [`multibody::Model`]s.
