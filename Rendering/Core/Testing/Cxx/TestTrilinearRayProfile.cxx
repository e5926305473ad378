int TestTrilinearRayProfile(int, char*[])
{
  return 1;
}
