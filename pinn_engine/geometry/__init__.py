"""Boundaries, sides and corners, planes, auxiliary lines, boundary fits, quad faces."""
