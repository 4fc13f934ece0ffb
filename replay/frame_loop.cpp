// Frame loop; being written.
