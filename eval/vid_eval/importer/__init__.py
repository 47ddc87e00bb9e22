"""vid-import: a flight log that is not a bag (CSV / HDF5 columns) -> the dataset folder of
docs/formats.md §1, in the project's frames (docs/design.md §3). docs/own-vehicle.md,
"Importing a log that is not a bag: vid-import"."""
