// Vulkan device; being written.
