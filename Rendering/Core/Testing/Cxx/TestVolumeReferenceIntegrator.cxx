int TestVolumeReferenceIntegrator(int, char*[])
{
  return 1;
}
