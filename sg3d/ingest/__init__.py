"""Perception: RGB-D frames -> local 3-D scene graphs (readers, ABIR, KGE, detection, SDR)."""
