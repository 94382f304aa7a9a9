"""The neural map: networks and their derivative jets, loss terms, the map with its boundary
built in, the trainer that knows no block kind, saved models."""
