pub mod planar;
