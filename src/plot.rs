//! Pictures of point sets: scatter plots with region boundaries, PNG and SVG, no system fonts.
