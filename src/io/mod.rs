//! File readers and writers: SWC, TrackVis .trk, MRtrix .tck, OBJ polylines, .npy.
