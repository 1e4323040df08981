"""Pure plane and space geometry: lines, arcs, intersections, offsets."""
