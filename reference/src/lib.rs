//! Drivers of external meshers (CGAL programs compiled by `cc`, command lines of TetGen).
